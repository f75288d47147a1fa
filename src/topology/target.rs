//! The expected topology of a target surface, and its Euler characteristic.

use crate::error::{Error, Result};

/// A target surface: orientable, `components` pieces each of genus `genus` with
/// `boundaries` holes in all (spread over the components).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct TargetTopology {
    pub genus: u32,
    pub boundaries: u32,
    pub components: u32,
}

impl TargetTopology {
    /// χ = Σ over components (2 − 2g − b): with `components` pieces of genus `genus`
    /// and `boundaries` holes in all, χ = 2c − 2cg − b.
    pub fn euler_characteristic(&self) -> i64 {
        let (g, b, c) = (
            i64::from(self.genus),
            i64::from(self.boundaries),
            i64::from(self.components),
        );
        2 * c - 2 * c * g - b
    }

    /// Parses `genus=0,boundaries=2[,components=1]` (keys in any order; defaults 0, 0, 1).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the bad key or value.
    pub fn parse(text: &str) -> Result<Self> {
        let mut t = TargetTopology {
            genus: 0,
            boundaries: 0,
            components: 1,
        };
        for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let (key, value) = part.split_once('=').ok_or_else(|| {
                Error::InvalidInput(format!("target {text:?}: {part:?} is not key=value"))
            })?;
            let n: u32 = value.trim().parse().map_err(|_| {
                Error::InvalidInput(format!("target {text:?}: {value:?} is not a whole number"))
            })?;
            match key.trim() {
                "genus" | "g" => t.genus = n,
                "boundaries" | "holes" | "b" => t.boundaries = n,
                "components" | "c" => t.components = n,
                other => {
                    return Err(Error::InvalidInput(format!(
                        "target {text:?}: unknown key {other:?} (genus, boundaries, components)"
                    )))
                }
            }
        }
        if t.components == 0 {
            return Err(Error::InvalidInput(format!(
                "target {text:?}: components must be at least 1"
            )));
        }
        Ok(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classic_surfaces() {
        let chi = |s: &str| TargetTopology::parse(s).unwrap().euler_characteristic();
        assert_eq!(chi("genus=0"), 2); // sphere
        assert_eq!(chi("genus=1"), 0); // torus
        assert_eq!(chi("genus=0,boundaries=1"), 1); // disk
        assert_eq!(chi("genus=0,boundaries=2"), 0); // annulus
        assert_eq!(chi("genus=0,boundaries=3"), -1); // the stamp's plate with two holes
        assert_eq!(chi("genus=0,components=9"), 18); // rabbit.obj
        assert!(TargetTopology::parse("genus=x").is_err());
        assert!(TargetTopology::parse("colour=1").is_err());
    }
}
