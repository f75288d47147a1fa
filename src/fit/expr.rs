//! Offset distances d(u, v) given as expressions by users (`0.2*math::sin(u - v)`),
//! through the evalexpr crate; variables `u` and `v`.

use evalexpr::{ContextWithMutableVariables, DefaultNumericTypes, HashMapContext, Node, Value};

use crate::error::{Error, Result};

/// A parsed expression in u and v.
#[derive(Debug, Clone)]
pub struct Expr {
    text: String,
    tree: Node<DefaultNumericTypes>,
}

impl Expr {
    /// Parses `text`.
    ///
    /// Errors: `InvalidInput` with evalexpr's message for a malformed expression.
    pub fn parse(text: &str) -> Result<Self> {
        let tree = evalexpr::build_operator_tree::<DefaultNumericTypes>(text)
            .map_err(|e| Error::InvalidInput(format!("expression {text:?}: {e}")))?;
        Ok(Self {
            text: text.to_string(),
            tree,
        })
    }

    /// The value at (u, v).
    ///
    /// Errors: `InvalidInput` if it does not evaluate to a finite number (unknown variable
    /// or function, division by zero, …).
    pub fn eval(&self, u: f64, v: f64) -> Result<f64> {
        let mut ctx = HashMapContext::<DefaultNumericTypes>::new();
        let bad = |e: evalexpr::EvalexprError<DefaultNumericTypes>| {
            Error::InvalidInput(format!("expression {:?} at ({u}, {v}): {e}", self.text))
        };
        ctx.set_value("u".into(), Value::Float(u)).map_err(bad)?;
        ctx.set_value("v".into(), Value::Float(v)).map_err(bad)?;
        let x = self.tree.eval_number_with_context(&ctx).map_err(bad)?;
        if !x.is_finite() {
            return Err(Error::InvalidInput(format!(
                "expression {:?} is {x} at ({u}, {v})",
                self.text
            )));
        }
        Ok(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::ROUND_OFF;

    #[test]
    fn evaluates_in_u_and_v() {
        let e = Expr::parse("0.2 * math::sin(0.5 * (u - v)^2 + 0.3)").unwrap();
        let want = 0.2 * (0.5 * (0.7f64 - 0.1).powi(2) + 0.3).sin();
        assert_near!(e.eval(0.7, 0.1).unwrap(), want, ROUND_OFF);
        assert_near!(
            Expr::parse("1").unwrap().eval(0.0, 0.0).unwrap(),
            1.0,
            ROUND_OFF
        );
        assert!(Expr::parse("u +").and_then(|e| e.eval(0.0, 0.0)).is_err());
        assert!(Expr::parse("(u").is_err());
        assert!(Expr::parse("w").unwrap().eval(0.0, 0.0).is_err());
        assert!(Expr::parse("1.0 / (u - u)")
            .unwrap()
            .eval(1.0, 0.0)
            .is_err());
    }
}
