//! The three spline methods on point arrays: the smoothing spline and its hole filling
//! (Kouibia & Pasadas 2022, biquadratic; 2024, Bogner–Fox–Schmit C¹ with shape
//! conditions), generalized offsets, and the 2004 smoothing spline with parallelism
//! conditions. Each gives a `Spline` that evaluates values and derivatives.

use std::collections::HashMap;

use numpy::{IntoPyArray, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::prelude::*;
use surfkit::fit::fill::FillVariant;
use surfkit::fit::parallel::{parallel_fit, ParallelFit, ParallelOptions};
use surfkit::fit::pipeline::{
    fit_and_fill, offset_data, FitOutcome, FitSetup, HoleSource, SpaceKind,
};
use surfkit::fit::shape::{ShapeConstraints, ShapePoint, Tau};
use surfkit::fit::{data::ScatteredData, Hole, HoleShape};
use surfkit::spline::{Hermite1d, Partition, TensorSpace};

use crate::errors::{natural, natural_usize, to_py, InvalidInput};

/// A solved spline surface (u, v) → (x, y, z).
#[pyclass(module = "surfkit._surfkit", frozen)]
pub struct Spline {
    solved: Solved,
}

enum Solved {
    /// `fit_and_fill`'s σ (the filled surface where there is a hole).
    Fill(Box<FitOutcome>),
    /// The 2004 method's s_ετ on BFS C².
    Parallel(Box<ParallelSpline>),
}

struct ParallelSpline {
    space: TensorSpace<Hermite1d>,
    fit: ParallelFit,
    report: String,
}

impl Spline {
    fn derivative_at(&self, u: f64, v: f64, a: usize, b: usize) -> surfkit::Result<[f64; 3]> {
        match &self.solved {
            Solved::Fill(outcome) => outcome.derivative(u, v, a, b),
            Solved::Parallel(p) => p.fit.spline.eval(&p.space, u, v, a, b),
        }
    }
}

#[pymethods]
impl Spline {
    /// ∂^(a+b)σ/∂u^a∂v^b at every (u[i], v[i]), an (n, 3) array; a point outside the
    /// parameter rectangle, or an order out of range or above the spline's degree, raises
    /// `InvalidInput` naming it.
    fn derivative<'py>(
        &self,
        py: Python<'py>,
        uv: PyReadonlyArray2<'py, f64>,
        a: &Bound<'py, PyAny>,
        b: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (a, b) = (natural_usize(a, "u order")?, natural_usize(b, "v order")?);
        let uv = uv.as_array();
        if uv.ncols() != 2 {
            return Err(InvalidInput::new_err(format!(
                "uv must have shape (n, 2), not {:?}",
                uv.shape()
            )));
        }
        let points: Vec<[f64; 2]> = uv.rows().into_iter().map(|r| [r[0], r[1]]).collect();
        let values = py.detach(|| {
            points
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    self.derivative_at(p[0], p[1], a, b)
                        .map_err(|e| format!("point {i} (u {}, v {}): {e}", p[0], p[1]))
                })
                .collect::<Result<Vec<[f64; 3]>, String>>()
        });
        let values = values.map_err(InvalidInput::new_err)?;
        let n = values.len();
        values.into_flattened().into_pyarray(py).reshape([n, 3])
    }

    /// The report (misfit, cells, the fill's constraints and jumps; for the 2004 method
    /// Π per point and the data misfit) as JSON.
    fn report_json(&self) -> PyResult<String> {
        match &self.solved {
            Solved::Fill(outcome) => serde_json::to_string(&outcome.summary),
            Solved::Parallel(p) => Ok(p.report.clone()),
        }
        .map_err(|e| InvalidInput::new_err(format!("the report as JSON: {e}")))
    }

    /// The solved coefficients as `surfkit fit --coefficients` writes them (not for the
    /// 2004 method, whose space the CLI does not write).
    fn coefficients_json(&self) -> PyResult<String> {
        match &self.solved {
            Solved::Fill(outcome) => serde_json::to_string(&outcome.coefficients())
                .map_err(|e| InvalidInput::new_err(format!("the coefficients as JSON: {e}"))),
            Solved::Parallel(_) => Err(InvalidInput::new_err(
                "coefficients are written for fit/fill splines only",
            )),
        }
    }
}

/// Rows of an (n, k) float array, every entry finite, or `InvalidInput` naming the row.
fn rows<const K: usize>(a: &PyReadonlyArray2<'_, f64>, what: &str) -> PyResult<Vec<[f64; K]>> {
    let a = a.as_array();
    if a.ncols() != K {
        return Err(InvalidInput::new_err(format!(
            "{what} must have shape (n, {K}), not {:?}",
            a.shape()
        )));
    }
    a.rows()
        .into_iter()
        .enumerate()
        .map(|(i, r)| {
            let row: [f64; K] = std::array::from_fn(|k| r[k]);
            if row.iter().all(|x| x.is_finite()) {
                Ok(row)
            } else {
                Err(InvalidInput::new_err(format!(
                    "{what}: row {i} has a non-finite entry {row:?}"
                )))
            }
        })
        .collect()
}

fn space(name: &str) -> PyResult<SpaceKind> {
    match name {
        "biquadratic" => Ok(SpaceKind::Biquadratic),
        "bicubic" => Ok(SpaceKind::Bicubic),
        "bfs-c1" => Ok(SpaceKind::BfsC1),
        other => Err(InvalidInput::new_err(format!(
            "space {other:?} is not one of 'biquadratic', 'bicubic', 'bfs-c1'"
        ))),
    }
}

/// A hole from the Python side's tuples: ("ellipse", cu, cv, a, b, level) or
/// ("polygon", [u0, v0, u1, v1, …]).
fn hole(shapes: Vec<(String, Vec<f64>)>) -> PyResult<Hole> {
    let shapes = shapes
        .into_iter()
        .enumerate()
        .map(|(i, (kind, numbers))| {
            if numbers.iter().any(|x| !x.is_finite()) {
                return Err(InvalidInput::new_err(format!(
                    "hole shape {i}: a non-finite number"
                )));
            }
            match (kind.as_str(), numbers.as_slice()) {
                ("ellipse", &[cu, cv, a, b, level]) => Ok(HoleShape::Ellipse {
                    center: [cu, cv],
                    coeffs: [a, b],
                    level,
                }),
                ("polygon", corners) if corners.len() >= 6 && corners.len() % 2 == 0 => Ok(
                    HoleShape::Polygon(corners.chunks_exact(2).map(|c| [c[0], c[1]]).collect()),
                ),
                _ => Err(InvalidInput::new_err(format!(
                    "hole shape {i}: expected ('ellipse', (cu, cv, a, b, level)) or \
                     ('polygon', [(u, v), …]) with at least 3 corners, got {kind:?} with {} \
                     numbers",
                    numbers.len()
                ))),
            }
        })
        .collect::<PyResult<_>>()?;
    Ok(Hole { shapes })
}

fn tau(value: i8, what: &str) -> PyResult<Option<Tau>> {
    match value {
        0 => Ok(None),
        1 => Ok(Some(Tau::Plus)),
        -1 => Ok(Some(Tau::Minus)),
        v => Err(InvalidInput::new_err(format!(
            "{what} {v} must be -1, 0 or +1"
        ))),
    }
}

/// Cells per side `(u, v)` from the Python pair, each an int ≥ 0 that fits a `usize`
/// (`InvalidInput` naming `cells[0]` or `cells[1]` otherwise; the methods check their own
/// bounds).
fn cells_from(cells: &(Bound<'_, PyAny>, Bound<'_, PyAny>)) -> PyResult<(usize, usize)> {
    Ok((
        natural_usize(&cells.0, "cells[0]")?,
        natural_usize(&cells.1, "cells[1]")?,
    ))
}

/// The 2024 shape conditions as the Python side passes them: (component, value, slope_u,
/// slope_v, lattice, points (k, 2)).
type PyShape<'py> = (
    Bound<'py, PyAny>,
    i8,
    i8,
    i8,
    Bound<'py, PyAny>,
    PyReadonlyArray2<'py, f64>,
);

/// Fits the smoothing spline to data `uv` (n, 2) → `xyz` (n, 3), optionally to a
/// generalized offset (`offset_distances` (n, 3): d₁, d₂, d₃ at each data point), and fills
/// the hole: `hole` shapes, or `hole_from_data` (cells without data). `shape` = (component,
/// value, slope_u, slope_v, lattice, points (k, 2)) turns on the 2024 shape conditions.
#[pyfunction]
#[pyo3(signature = (uv, xyz, *, space_name, cells, epsilon, hole_shapes, hole_from_data, exact_c1, offset_distances, shape))]
#[allow(clippy::too_many_arguments)]
// Each argument is a keyword argument of the Python functions fit and fill.
pub fn fit_spline(
    py: Python<'_>,
    uv: PyReadonlyArray2<'_, f64>,
    xyz: PyReadonlyArray2<'_, f64>,
    space_name: &str,
    cells: (Bound<'_, PyAny>, Bound<'_, PyAny>),
    epsilon: f64,
    hole_shapes: Vec<(String, Vec<f64>)>,
    hole_from_data: bool,
    exact_c1: bool,
    offset_distances: Option<PyReadonlyArray2<'_, f64>>,
    shape: Option<PyShape<'_>>,
) -> PyResult<Spline> {
    let cells = cells_from(&cells)?;
    let params = rows::<2>(&uv, "uv")?;
    let points = rows::<3>(&xyz, "xyz")?;
    if params.len() != points.len() {
        return Err(InvalidInput::new_err(format!(
            "{} parameters (uv) for {} points (xyz)",
            params.len(),
            points.len()
        )));
    }
    if !(epsilon > 0.0 && epsilon.is_finite()) {
        return Err(InvalidInput::new_err(format!(
            "epsilon {epsilon} must be a finite number > 0"
        )));
    }
    let hole = match (hole_shapes.is_empty(), hole_from_data) {
        (true, false) => HoleSource::None,
        (true, true) => HoleSource::CellsWithoutData,
        (false, false) => HoleSource::Shapes(hole(hole_shapes)?),
        (false, true) => {
            return Err(InvalidInput::new_err(
                "give hole shapes or hole_from_data, not both",
            ))
        }
    };
    let shape = match shape {
        None => None,
        Some((component, value, slope_u, slope_v, lattice, extra)) => {
            // 0, 1 or 2: x, y or z.
            let component = natural(&component, "shape_component", 2)? as usize;
            let lattice = natural_usize(&lattice, "shape_lattice")?;
            Some(ShapeConstraints {
                component,
                value: tau(value, "shape value")?,
                slope_x: tau(slope_u, "shape slope_u")?,
                slope_y: tau(slope_v, "shape slope_v")?,
                extra_per_side: lattice,
                extra_points: rows::<2>(&extra, "shape points")?
                    .into_iter()
                    .enumerate()
                    .map(|(i, uv)| ShapePoint {
                        uv,
                        label: format!("shape point {i}"),
                    })
                    .collect(),
            })
        }
    };
    let setup = FitSetup {
        space: space(space_name)?,
        cells: [cells.0, cells.1],
        epsilon,
        hole,
        variant: if exact_c1 {
            FillVariant::ExactC1
        } else {
            FillVariant::Paper
        },
        shape,
    };
    let distances = match offset_distances {
        None => None,
        Some(d) => {
            let d = rows::<3>(&d, "offset distances")?;
            if d.len() != params.len() {
                return Err(InvalidInput::new_err(format!(
                    "{} offset distances for {} data points",
                    d.len(),
                    params.len()
                )));
            }
            Some(d)
        }
    };
    let data = ScatteredData { params, points };
    let outcome = py
        .detach(|| -> surfkit::Result<FitOutcome> {
            let data = match &distances {
                None => data,
                Some(d) => {
                    // The distances are a function of (u, v): look them up by the parameter.
                    let at: HashMap<[u64; 2], [f64; 3]> = data
                        .params
                        .iter()
                        .zip(d)
                        .map(|(p, d)| ([p[0].to_bits(), p[1].to_bits()], *d))
                        .collect();
                    offset_data(&data, &setup, &|u, v| {
                        at.get(&[u.to_bits(), v.to_bits()]).copied().ok_or_else(|| {
                            surfkit::Error::InvalidInput(format!(
                                "no offset distance at ({u}, {v})"
                            ))
                        })
                    })?
                }
            };
            fit_and_fill(&data, &setup)
        })
        .map_err(to_py)?;
    Ok(Spline {
        solved: Solved::Fill(Box::new(outcome)),
    })
}

/// The discrete smoothing variational spline with parallelism conditions (2004 §4): data
/// `uv` → `xyz`, points `b_uv` where the tangent planes should be parallel to the
/// reference surface's, whose unit normals there are `normals`; BFS C² on `cells` over the
/// rectangle of all parameters; J = Σ‖y(a) − pₐ‖² + τΠ + ε|y|²ₘ (4.3).
#[pyfunction]
#[pyo3(signature = (uv, xyz, b_uv, normals, *, cells, epsilon, tau, m))]
#[allow(clippy::too_many_arguments)]
// Each argument is a keyword argument of the Python function.
pub fn fit_parallel(
    py: Python<'_>,
    uv: PyReadonlyArray2<'_, f64>,
    xyz: PyReadonlyArray2<'_, f64>,
    b_uv: PyReadonlyArray2<'_, f64>,
    normals: PyReadonlyArray2<'_, f64>,
    cells: (Bound<'_, PyAny>, Bound<'_, PyAny>),
    epsilon: f64,
    tau: f64,
    m: &Bound<'_, PyAny>,
) -> PyResult<Spline> {
    let cells = cells_from(&cells)?;
    let m = natural_usize(m, "m")?;
    let (a, values) = (rows::<2>(&uv, "uv")?, rows::<3>(&xyz, "xyz")?);
    let (b, normals) = (rows::<2>(&b_uv, "b_uv")?, rows::<3>(&normals, "normals")?);
    if a.is_empty() {
        return Err(InvalidInput::new_err("no data points"));
    }
    if cells.0 == 0 || cells.1 == 0 || cells.0.saturating_mul(cells.1) > 64 * 64 {
        return Err(InvalidInput::new_err(format!(
            "cells {cells:?}: need 1 to 4096 cells, at least one per side"
        )));
    }
    let range = |k: usize| {
        a.iter()
            .chain(&b)
            .map(|p| p[k])
            .fold([f64::INFINITY, f64::NEG_INFINITY], |r, x| {
                [r[0].min(x), r[1].max(x)]
            })
    };
    let (ru, rv) = (range(0), range(1));
    if !(ru[0] < ru[1] && rv[0] < rv[1]) {
        return Err(InvalidInput::new_err(format!(
            "the parameters span a degenerate rectangle {ru:?} × {rv:?}"
        )));
    }
    let solved = py
        .detach(
            || -> surfkit::Result<(TensorSpace<Hermite1d>, ParallelFit)> {
                let space = TensorSpace::bfs_c2(
                    Partition::uniform(ru[0], ru[1], cells.0)?,
                    Partition::uniform(rv[0], rv[1], cells.1)?,
                )?;
                let options = ParallelOptions { epsilon, tau, m };
                let fit = parallel_fit(&space, &a, &values, &b, &normals, &options)?;
                Ok((space, fit))
            },
        )
        .map_err(to_py)?;
    let (space, fit) = solved;
    let report = serde_json::json!({
        "method": "kp2004-parallelism",
        "space": "bfs-c2",
        "cells": [cells.0, cells.1],
        "u_range": ru,
        "v_range": rv,
        "epsilon": epsilon,
        "tau": tau,
        "m": m,
        "points": a.len(),
        "parallelism_points": b.len(),
        "system_dimension": fit.system_dimension,
        "pi_per_point": fit.pi_per_point,
        "data_misfit": fit.data_misfit,
    })
    .to_string();
    Ok(Spline {
        solved: Solved::Parallel(Box::new(ParallelSpline { space, fit, report })),
    })
}
