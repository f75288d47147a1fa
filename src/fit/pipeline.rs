//! The users' pipeline behind `surfkit fit` / `surfkit fill`: scattered (u, v) → (x, y, z)
//! data, a spline space on the data's parameter rectangle, the smoothing spline σ₁
//! (2022 (8)) and, when a hole is given or read off the data, the filled σ (2022 §4).

use serde::Serialize;

use crate::error::{Error, Result};
use crate::mesh::PolygonMesh;
use crate::spline::{Grid, Partition, Space, TensorSpace};

use super::data::ScatteredData;
use super::fill::border_jumps;
use super::fill::{fill_hole, FillOptions, FillReport, FillVariant, HoleFill};
use super::hole::{cells_without_data, Hole, HoleShape};
use super::sample::sample_mesh;
use super::shape::{shape_preserving_fill, ShapeConstraints, ShapeReport};
use super::smoothing::{smoothing_spline, SmoothingOptions};
use super::surface::VectorSpline;

/// The spline space to fit with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum SpaceKind {
    /// Biquadratic C¹ B-splines, S₂(Tₙ, Tₘ) (2022).
    Biquadratic,
    /// Bicubic C² B-splines.
    Bicubic,
    /// Bogner–Fox–Schmit C¹ (2024).
    BfsC1,
}

/// Where the hole is.
#[derive(Debug, Clone, PartialEq)]
pub enum HoleSource {
    /// No hole: fit only.
    None,
    /// Given shapes.
    Shapes(Hole),
    /// The cells that hold no data point.
    CellsWithoutData,
}

/// The setup of a fit.
#[derive(Debug, Clone)]
pub struct FitSetup {
    pub space: SpaceKind,
    /// Cells along u and v.
    pub cells: [usize; 2],
    /// ε > 0 for σ₁ and σ₂.
    pub epsilon: f64,
    pub hole: HoleSource,
    pub variant: FillVariant,
    /// Shape conditions on the filled part (2024 §4, (10)–(11)): with them the hole is
    /// filled by [`shape_preserving_fill`] (BFS C¹ only) instead of the 2022 method.
    pub shape: Option<ShapeConstraints>,
}

/// What the pipeline did.
#[derive(Debug, Clone, Serialize)]
pub struct FitSummary {
    pub points: usize,
    pub space: SpaceKind,
    pub cells: [usize; 2],
    pub dimension_per_component: usize,
    pub epsilon: f64,
    pub u_range: [f64; 2],
    pub v_range: [f64; 2],
    /// RMS and max of ‖σ(a) − pₐ‖ over the data.
    pub rms_misfit: f64,
    pub max_misfit: f64,
    /// Cells without data (determined by the semi-norm only).
    pub empty_cells: usize,
    /// Cells of H_h (0 without a hole).
    pub hole_cells: usize,
    pub fill: Option<FillReport>,
    /// The shape-preserving fill's constraints and their violations (with `shape`).
    pub shape: Option<ShapeReport>,
}

/// The solved surfaces.
pub struct FitOutcome {
    pub space: Box<dyn Space>,
    pub sigma1: VectorSpline,
    pub fill: Option<HoleFill>,
    pub summary: FitSummary,
}

/// The solved coefficients, as written to JSON: the space is rebuilt from `summary`
/// (kind, cells, parameter ranges); σ₂'s coefficients apply on the `hole_cells`.
#[derive(Debug, Clone, Serialize)]
pub struct CoefficientsFile<'a> {
    pub summary: &'a FitSummary,
    pub sigma1: &'a VectorSpline,
    pub sigma2: Option<&'a VectorSpline>,
    /// H_h by cell index i·ny + j (i along u).
    pub hole_cells: Option<&'a [bool]>,
}

impl FitOutcome {
    /// The coefficients for JSON output.
    pub fn coefficients(&self) -> CoefficientsFile<'_> {
        CoefficientsFile {
            summary: &self.summary,
            sigma1: &self.sigma1,
            sigma2: self.fill.as_ref().map(|f| &f.sigma2),
            hole_cells: self.fill.as_ref().map(|f| f.hole_cells.as_slice()),
        }
    }

    /// σ (the filled surface if there is one, else σ₁) at (u, v).
    ///
    /// Errors: outside the rectangle.
    pub fn eval(&self, u: f64, v: f64) -> Result<[f64; 3]> {
        self.derivative(u, v, 0, 0)
    }

    /// ∂^(a+b)σ / ∂u^a ∂v^b at (u, v), from the cell holding the point (σ is C¹ in the
    /// spline spaces; higher derivatives are the cell's polynomial's).
    ///
    /// Errors: outside the rectangle, or an order above the space's degree.
    pub fn derivative(&self, u: f64, v: f64, a: usize, b: usize) -> Result<[f64; 3]> {
        let degree = self.space.degree();
        if a.max(b) > degree {
            return Err(Error::InvalidInput(format!(
                "derivative order ({a}, {b}) is above the spline's degree {degree}"
            )));
        }
        match &self.fill {
            Some(f) => f.eval(self.space.as_ref(), u, v, a, b),
            None => self.sigma1.eval(self.space.as_ref(), u, v, a, b),
        }
    }

    /// A res × res quad mesh of σ, quality = RMS misfit of the data in each vertex's cell
    /// (0 in cells without data).
    ///
    /// Errors: as [`sample_mesh`].
    pub fn mesh(&self, data: &ScatteredData, res: usize) -> Result<PolygonMesh> {
        let g = self.space.grid();
        // Per cell: the largest misfit and the sum of squares scaled by it, so that the RMS
        // of misfits near f64::MAX does not overflow to inf.
        let mut scale = vec![0.0f64; g.cell_count()];
        let mut sq = vec![0.0f64; g.cell_count()];
        let mut count = vec![0usize; g.cell_count()];
        for (i, (p, x)) in data.params.iter().zip(&data.points).enumerate() {
            let c = g.locate(p[0], p[1]).ok_or_else(|| {
                Error::InvalidInput(format!(
                    "data point {i} at (u, v) = ({}, {}) lies outside the spline's rectangle",
                    p[0], p[1]
                ))
            })?;
            let s = self.eval(p[0], p[1])?;
            let k = g.cell_index(c);
            for d in (0..3).map(|j| (s[j] - x[j]).abs()) {
                if d > scale[k] {
                    sq[k] = 1.0 + sq[k] * (scale[k] / d).powi(2);
                    scale[k] = d;
                } else if d > 0.0 {
                    sq[k] += (d / scale[k]).powi(2);
                }
            }
            count[k] += 1;
        }
        let q = |u: f64, v: f64| -> Result<f64> {
            let c = g.locate(u, v).ok_or_else(|| {
                Error::InvalidInput(format!("sample ({u}, {v}) outside the spline's rectangle"))
            })?;
            let k = g.cell_index(c);
            let rms = if count[k] == 0 {
                0.0
            } else {
                scale[k] * (sq[k] / count[k] as f64).sqrt()
            };
            if rms.is_finite() {
                Ok(rms)
            } else {
                Err(Error::InvalidInput(format!(
                    "the misfit at ({u}, {v}) is not finite: the data or the spline passes \
                     the range of f64 (scale the data down)"
                )))
            }
        };
        let (u, v) = g.bounds();
        sample_mesh(u, v, res, &|a, b| self.eval(a, b), Some(&q))
    }
}

fn range(v: impl Iterator<Item = f64>) -> [f64; 2] {
    v.fold([f64::INFINITY, f64::NEG_INFINITY], |r, x| {
        [r[0].min(x), r[1].max(x)]
    })
}

/// Most cells of a fit: checked before anything is allocated, so an absurd request is an
/// error and not an allocation failure (which would abort the process).
pub const MAX_CELLS: usize = 1 << 20;

/// Largest data magnitude a fit accepts: the normal equations sum squares of the data, which
/// overflow f64 past about 1e154.
pub const MAX_DATA_MAGNITUDE: f64 = 1e150;

/// Fits σ₁ to the data on the parameter rectangle and fills the hole if any.
///
/// Errors: `InvalidInput` for fewer than 1 cell per side, a degenerate parameter range,
/// ε ≤ 0, a cell outside the hole without data (too few points to determine the spline
/// there), or the ill-posed cases of [`smoothing_spline`] and [`fill_hole`] (too few or
/// collinear points, a hole covering every cell, …); solver errors.
pub fn fit_and_fill(data: &ScatteredData, setup: &FitSetup) -> Result<FitOutcome> {
    if setup.cells[0] == 0 || setup.cells[1] == 0 {
        return Err(Error::InvalidInput(
            "need at least one cell per side".into(),
        ));
    }
    let too_large = |x: &f64| x.abs() > MAX_DATA_MAGNITUDE;
    if let Some(i) = data.points.iter().position(|p| p.iter().any(too_large)) {
        return Err(Error::InvalidInput(format!(
            "data point {i} (data line {}) has a coordinate of magnitude above \
             {MAX_DATA_MAGNITUDE:e}: {:?}; the fit's sums of squares would overflow, scale the \
             data to sensible units",
            i + 1,
            data.points[i]
        )));
    }
    if let Some(i) = data.params.iter().position(|p| p.iter().any(too_large)) {
        return Err(Error::InvalidInput(format!(
            "data point {i} has a parameter of magnitude above {MAX_DATA_MAGNITUDE:e}: {:?}",
            data.params[i]
        )));
    }
    if setup.cells[0].saturating_mul(setup.cells[1]) > MAX_CELLS {
        return Err(Error::InvalidInput(format!(
            "{} × {} cells: at most {MAX_CELLS} cells are supported (the Gram matrices grow \
             with the cell count; the papers' examples use at most 32 × 32)",
            setup.cells[0], setup.cells[1]
        )));
    }
    if data.params.len() != data.points.len() || data.params.is_empty() {
        return Err(Error::InvalidInput(
            "no data, or parameters and points of different counts".into(),
        ));
    }
    if let Some(shape) = &setup.shape {
        if setup.space != SpaceKind::BfsC1 {
            return Err(Error::InvalidInput(format!(
                "shape constraints (2024 §4) need the Bogner–Fox–Schmit C¹ space (bfs-c1), not {:?}: \
                 its nodal degrees of freedom are what the boundary interpolation fixes",
                setup.space
            )));
        }
        if setup.hole == HoleSource::None {
            return Err(Error::InvalidInput(
                "shape constraints apply to the filled hole: give a hole (or cells without data)"
                    .into(),
            ));
        }
        if setup.variant == FillVariant::ExactC1 {
            return Err(Error::InvalidInput(
                "shape constraints and the exact-C¹ variant are exclusive: the shape-preserving \
                 fill interpolates every nodal degree of freedom on the hole's border, so it is \
                 already C¹ there"
                    .into(),
            ));
        }
        if shape.value.is_none() && shape.slope_x.is_none() && shape.slope_y.is_none() {
            return Err(Error::InvalidInput(
                "shape constraints without any condition (positivity or monotonicity)".into(),
            ));
        }
        if shape.component > 2 {
            return Err(Error::InvalidInput(format!(
                "shape constraint component {} (expected 0, 1 or 2 for x, y, z)",
                shape.component
            )));
        }
    }
    let u = range(data.params.iter().map(|p| p[0]));
    let v = range(data.params.iter().map(|p| p[1]));
    if !(u[0] < u[1] && v[0] < v[1]) {
        return Err(Error::InvalidInput(format!(
            "the parameters span a degenerate rectangle {u:?} × {v:?}"
        )));
    }
    let (px, py) = (
        Partition::uniform(u[0], u[1], setup.cells[0])?,
        Partition::uniform(v[0], v[1], setup.cells[1])?,
    );
    let space: Box<dyn Space> = match setup.space {
        SpaceKind::Biquadratic => Box::new(TensorSpace::bspline(px.clone(), py.clone(), 2)?),
        SpaceKind::Bicubic => Box::new(TensorSpace::bspline(px.clone(), py.clone(), 3)?),
        SpaceKind::BfsC1 => Box::new(TensorSpace::bfs_c1(px.clone(), py.clone())?),
    };
    let grid: Grid = space.grid().clone();
    let mask = match &setup.hole {
        HoleSource::None => None,
        HoleSource::Shapes(h) => Some(h.cells(&grid)?),
        HoleSource::CellsWithoutData => {
            let cells = cells_without_data(&grid, &data.params);
            if cells.is_empty() {
                None
            } else {
                Some(
                    Hole {
                        shapes: vec![HoleShape::Cells(cells)],
                    }
                    .cells(&grid)?,
                )
            }
        }
    };
    // Ill-posed: a cell outside the hole without data is determined by the smoothing term
    // alone — refuse it rather than return an unsupported surface.
    let empty = cells_without_data(&grid, &data.params);
    if let Some(c) = empty
        .iter()
        .find(|c| mask.as_ref().is_none_or(|m| !m[grid.cell_index(**c)]))
    {
        return Err(Error::InvalidInput(format!(
            "{} cell(s) outside any hole hold no data point (first: cell ({}, {}) of {}×{}): use fewer cells or fill them as a hole",
            empty.iter().filter(|c| mask.as_ref().is_none_or(|m| !m[grid.cell_index(**c)])).count(),
            c.i,
            c.j,
            setup.cells[0],
            setup.cells[1]
        )));
    }
    // After the checks that need no solve.
    let fit = smoothing_spline(
        space.as_ref(),
        &data.params,
        &data.points,
        &[],
        &SmoothingOptions {
            epsilon: setup.epsilon,
            m: 2,
            domain: None,
        },
    )?;
    let mut shape_report = None;
    let fill =
        match (&mask, &setup.shape) {
            (Some(m), Some(shape)) => {
                // 2024 (11): σ̄₂ = argmin |v|₂,H_h with σ₁'s nodal dofs on ∂H_h and τL(v) ≥ 0.
                let bfs = TensorSpace::bfs_c1(px.clone(), py.clone())?;
                let filled = shape_preserving_fill(&bfs, &fit.spline, m, 2, shape)?;
                let (c0, c1) = border_jumps(&bfs, &fit.spline, &filled.spline, m)?;
                shape_report = Some(filled.report.clone());
                Some(HoleFill {
                    sigma1: fit.spline.clone(),
                    sigma2: filled.spline,
                    hole_cells: m.clone(),
                    report: FillReport {
                        unknowns: filled.report.unknowns,
                        c0_jump: c0,
                        c1_jump: c1,
                        ..Default::default()
                    },
                })
            }
            (Some(m), None) => Some(fill_hole(
                space.as_ref(),
                &fit.spline,
                &data.params,
                m,
                &FillOptions {
                    epsilon: setup.epsilon,
                    m: 2,
                    variant: setup.variant,
                },
            )?),
            (None, Some(_)) => return Err(Error::InvalidInput(
                "shape constraints were given but there is no hole to fill: every cell holds data"
                    .into(),
            )),
            (None, None) => None,
        };
    let mut out = FitOutcome {
        space,
        sigma1: fit.spline,
        fill,
        summary: FitSummary {
            points: data.params.len(),
            space: setup.space,
            cells: setup.cells,
            dimension_per_component: 0,
            epsilon: setup.epsilon,
            u_range: u,
            v_range: v,
            rms_misfit: 0.0,
            max_misfit: 0.0,
            empty_cells: fit.empty_cells,
            hole_cells: mask
                .as_ref()
                .map_or(0, |m| m.iter().filter(|&&b| b).count()),
            fill: None,
            shape: shape_report,
        },
    };
    out.summary.dimension_per_component = out.space.dim();
    out.summary.fill = out.fill.as_ref().map(|f| f.report.clone());
    let (mut sq, mut mx) = (0.0f64, 0.0f64);
    for (p, x) in data.params.iter().zip(&data.points) {
        let s = out.eval(p[0], p[1])?;
        let e = (0..3).map(|k| (s[k] - x[k]).powi(2)).sum::<f64>();
        sq += e;
        mx = mx.max(e.sqrt());
    }
    out.summary.rms_misfit = (sq / data.params.len() as f64).sqrt();
    out.summary.max_misfit = mx;
    Ok(out)
}

/// The data of a generalized offset of the surface the data sample (2022 (3)): fits σ_f
/// to the data, takes the frame (e₁, e₂, n) of σ_f at each parameter (2022 (2)) and returns
/// pₐ + d₁e₁ + d₂e₂ + d₃n with `distances(u, v) = (d₁, d₂, d₃)`. σ_f is fitted with the
/// setup's hole, so that cells the hole leaves without data are allowed; its fill is not
/// needed (the frames are taken at the data).
///
/// Errors: those of [`fit_and_fill`]; `InvalidInput` where σ_f is not regular or a
/// distance fails.
pub fn offset_data(
    data: &ScatteredData,
    setup: &FitSetup,
    distances: &dyn Fn(f64, f64) -> Result<[f64; 3]>,
) -> Result<ScatteredData> {
    let base = fit_and_fill(
        data,
        &FitSetup {
            shape: None,
            ..setup.clone()
        },
    )?;
    let space = base.space.as_ref();
    let mut out = ScatteredData::default();
    for (p, x) in data.params.iter().zip(&data.points) {
        let fu = base.sigma1.eval(space, p[0], p[1], 1, 0)?;
        let fv = base.sigma1.eval(space, p[0], p[1], 0, 1)?;
        let surface = move |_: f64, _: f64| [*x, fu, fv];
        let frame = super::offset::GeneralizedOffset {
            surface,
            distances: [
                Box::new(|_, _| 0.0),
                Box::new(|_, _| 0.0),
                Box::new(|_, _| 0.0),
            ],
        }
        .frame(p[0], p[1])?;
        let d = distances(p[0], p[1])?;
        out.params.push(*p);
        out.points.push(std::array::from_fn(|k| {
            x[k] + d[0] * frame[0][k] + d[1] * frame[1][k] + d[2] * frame[2][k]
        }));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tolerance::SOLVE;

    /// The height field (u, v, z(u, v)) sampled on an n × n grid of [0, 1]², without the
    /// samples in the square [0.4, 0.6]² when `gap`.
    fn grid_samples(n: usize, gap: bool, z: impl Fn(f64, f64) -> f64) -> ScatteredData {
        let mut d = ScatteredData::default();
        let step = (n - 1) as f64;
        for i in 0..n {
            for j in 0..n {
                let (u, v) = (i as f64 / step, j as f64 / step);
                if gap && (0.4..=0.6).contains(&u) && (0.4..=0.6).contains(&v) {
                    continue;
                }
                d.params.push([u, v]);
                d.points.push([u, v, z(u, v)]);
            }
        }
        d
    }

    #[test]
    fn fits_a_quadratic_patch_and_fills_the_empty_cells() {
        // Data of an affine map on [0,1]² with a square gap [0.4, 0.6]²: a fit with 5 × 5
        // cells leaves cell (2, 2) empty; the filled surface reproduces the affine map.
        let d = grid_samples(40, true, |u, v| 1.0 + u - 2.0 * v);
        for space in [SpaceKind::Biquadratic, SpaceKind::Bicubic, SpaceKind::BfsC1] {
            let setup = FitSetup {
                space,
                cells: [5, 5],
                epsilon: 1e-6,
                hole: HoleSource::CellsWithoutData,
                variant: FillVariant::Paper,
                shape: None,
            };
            let out = fit_and_fill(&d, &setup).unwrap();
            assert_eq!(out.summary.hole_cells, 1);
            let s = out.eval(0.5, 0.5).unwrap();
            crate::assert_near!(s[2], 1.0 + 0.5 - 1.0, SOLVE);
            let m = out.mesh(&d, 8).unwrap();
            assert_eq!(m.vertex_count(), 81);
        }
    }

    #[test]
    fn normal_offset_of_a_plane_is_a_shifted_plane() {
        // f(u, v) = (u, v, 0.5u): n = (−0.5, 0, 1)/√1.25; d₃ = 0.1 shifts every point by 0.1n.
        let d = grid_samples(15, false, |u, _| 0.5 * u);
        let setup = FitSetup {
            space: SpaceKind::Biquadratic,
            cells: [3, 3],
            epsilon: 1e-9,
            hole: HoleSource::None,
            variant: FillVariant::Paper,
            shape: None,
        };
        let o = offset_data(&d, &setup, &|_, _| Ok([0.0, 0.0, 0.1])).unwrap();
        let s = 0.1 / 1.25f64.sqrt();
        for (p, q) in d.points.iter().zip(&o.points) {
            crate::assert_near!(q[0] - p[0], -0.5 * s, SOLVE);
            crate::assert_near!(q[1] - p[1], 0.0, SOLVE);
            crate::assert_near!(q[2] - p[2], s, SOLVE);
        }
    }

    #[test]
    fn the_offset_of_data_with_a_gap_is_filled_across_it() {
        // The plane f(u, v) = (u, v, 0.5u) sampled with a square gap [0.4, 0.6]²: 5 × 5 cells
        // leave cell (2, 2) without data, the hole. The offset data are the points shifted
        // by 0.1n, and the filled offset surface is that shifted plane in the gap too.
        let d = grid_samples(40, true, |u, _| 0.5 * u);
        let setup = FitSetup {
            space: SpaceKind::Biquadratic,
            cells: [5, 5],
            epsilon: 1e-9,
            hole: HoleSource::CellsWithoutData,
            variant: FillVariant::Paper,
            shape: None,
        };
        let o = offset_data(&d, &setup, &|_, _| Ok([0.0, 0.0, 0.1])).unwrap();
        let s = 0.1 / 1.25f64.sqrt();
        let shifted = |p: [f64; 3]| [p[0] - 0.5 * s, p[1], p[2] + s];
        for (p, q) in d.points.iter().zip(&o.points) {
            let expected = shifted(*p);
            for k in 0..3 {
                crate::assert_near!(q[k], expected[k], SOLVE);
            }
        }
        let filled = fit_and_fill(&o, &setup).unwrap();
        assert_eq!(filled.summary.hole_cells, 1);
        // The offset surface's parameters are the data's: at (0.5, 0.5), inside the gap,
        // it passes through the shifted plane's point over f(0.5, 0.5).
        let centre = filled.eval(0.5, 0.5).unwrap();
        let expected = shifted([0.5, 0.5, 0.25]);
        for k in 0..3 {
            crate::assert_near!(centre[k], expected[k], 1e-6);
        }
    }

    #[test]
    fn ill_posed_setups_are_errors() {
        let d = ScatteredData {
            params: vec![[0.0, 0.0], [1.0, 1.0]],
            points: vec![[0.0; 3]; 2],
        };
        let setup = FitSetup {
            space: SpaceKind::Biquadratic,
            cells: [2, 2],
            epsilon: 1e-6,
            hole: HoleSource::None,
            variant: FillVariant::Paper,
            shape: None,
        };
        assert!(fit_and_fill(&d, &setup).is_err(), "two points");
        let line = ScatteredData {
            params: vec![[0.0, 0.0]; 5],
            points: vec![[0.0; 3]; 5],
        };
        assert!(fit_and_fill(&line, &setup).is_err(), "degenerate rectangle");
        assert!(fit_and_fill(
            &d,
            &FitSetup {
                epsilon: 0.0,
                ..setup.clone()
            }
        )
        .is_err());
        assert!(fit_and_fill(
            &d,
            &FitSetup {
                cells: [0, 2],
                ..setup
            }
        )
        .is_err());
    }
}
