//! Catmull–Clark through OpenSubdiv: uniform refinement into a new `Mesh`, and the limit
//! surface (`LimitSurface`) evaluated at ptex-face points into numpy arrays.

use numpy::{IntoPyArray, PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use surfkit::subdiv::{
    limit_surface, refine_uniform, BoundaryInterpolation, Corner, Crease, CreasingMethod,
    PatchOptions, PatchSurface, SubdivOptions,
};

use crate::errors::{natural, natural_u32, natural_usize, to_py, InvalidInput, TopologyError};
use crate::mesh::Mesh;

/// A crease as the Python side passes it: (v0, v1, sharpness).
type PyCrease<'py> = (Bound<'py, PyAny>, Bound<'py, PyAny>, f32);
/// A corner as the Python side passes it: (v, sharpness).
type PyCorner<'py> = (Bound<'py, PyAny>, f32);

/// The subdivision options from the Python arguments (names as `surfkit subdivide`);
/// vertex ids outside 32 bits raise `InvalidInput` naming the crease or corner.
pub fn subdiv_options(
    boundary: &str,
    creases: Vec<PyCrease<'_>>,
    corners: Vec<PyCorner<'_>>,
    creasing: &str,
) -> PyResult<SubdivOptions> {
    let boundary = match boundary {
        "edges-and-corners" => BoundaryInterpolation::EdgesAndCorners,
        "edges-only" => BoundaryInterpolation::EdgesOnly,
        "none" => BoundaryInterpolation::None,
        other => {
            return Err(InvalidInput::new_err(format!(
                "boundary {other:?} is not one of 'edges-and-corners', 'edges-only', 'none'"
            )))
        }
    };
    let creasing = match creasing {
        "uniform" => CreasingMethod::Uniform,
        "chaikin" => CreasingMethod::Chaikin,
        other => {
            return Err(InvalidInput::new_err(format!(
                "creasing {other:?} is not one of 'uniform', 'chaikin'"
            )))
        }
    };
    let sharp = |s: f32, what: String| -> PyResult<f32> {
        if s.is_finite() && s >= 0.0 {
            Ok(s)
        } else {
            Err(InvalidInput::new_err(format!(
                "{what}: sharpness {s} must be a finite number ≥ 0"
            )))
        }
    };
    Ok(SubdivOptions {
        creases: creases
            .into_iter()
            .enumerate()
            .map(|(i, (a, b, s))| {
                Ok(Crease {
                    vertices: [
                        natural_u32(&a, &format!("crease {i}: vertex"))?,
                        natural_u32(&b, &format!("crease {i}: vertex"))?,
                    ],
                    sharpness: sharp(s, format!("crease {i}"))?,
                })
            })
            .collect::<PyResult<_>>()?,
        corners: corners
            .into_iter()
            .enumerate()
            .map(|(i, (v, s))| {
                Ok(Corner {
                    vertex: natural_u32(&v, &format!("corner {i}: vertex"))?,
                    sharpness: sharp(s, format!("corner {i}"))?,
                })
            })
            .collect::<PyResult<_>>()?,
        boundary,
        creasing,
        ..Default::default()
    })
}

/// `levels` uniform Catmull–Clark refinements (GIL released); the control vertices keep
/// their ids, new vertices follow.
#[pyfunction]
#[pyo3(signature = (mesh, levels, *, boundary, creases, corners, creasing))]
pub fn subdivide(
    py: Python<'_>,
    mesh: &Mesh,
    levels: &Bound<'_, PyAny>,
    boundary: &str,
    creases: Vec<PyCrease<'_>>,
    corners: Vec<PyCorner<'_>>,
    creasing: &str,
) -> PyResult<Mesh> {
    let levels = natural_u32(levels, "levels")?;
    let options = subdiv_options(boundary, creases, corners, creasing)?;
    let input = &mesh.mesh;
    let refined = py
        .detach(|| refine_uniform(input, levels, &options))
        .map_err(to_py)?;
    Ok(Mesh { mesh: refined })
}

/// The limit surface of a control mesh as bicubic patches (OpenSubdiv's feature-adaptive
/// table, end caps after `max_isolation` levels).
#[pyclass(module = "surfkit._surfkit", frozen)]
pub struct LimitSurface {
    surface: PatchSurface,
}

#[pymethods]
impl LimitSurface {
    #[new]
    #[pyo3(signature = (mesh, *, max_isolation, boundary, creases, corners, creasing))]
    fn new(
        py: Python<'_>,
        mesh: &Mesh,
        max_isolation: &Bound<'_, PyAny>,
        boundary: &str,
        creases: Vec<PyCrease<'_>>,
        corners: Vec<PyCorner<'_>>,
        creasing: &str,
    ) -> PyResult<Self> {
        let max_isolation = natural_u32(max_isolation, "max_isolation")?;
        let options = subdiv_options(boundary, creases, corners, creasing)?;
        let patch_options = PatchOptions {
            max_isolation,
            ..PatchOptions::default()
        };
        let input = &mesh.mesh;
        let surface = py
            .detach(|| limit_surface(input, &options, &patch_options))
            .map_err(to_py)?;
        Ok(LimitSurface { surface })
    }

    /// The number of ptex faces (one per quad, n per n-gon).
    #[getter]
    fn ptex_face_count(&self) -> usize {
        self.surface.ptex_face_count()
    }

    /// The ptex faces of control face `face` as (first, count); an n-gon's ptex face i
    /// starts at its corner i.
    fn ptex_faces(&self, face: &Bound<'_, PyAny>) -> PyResult<(u32, u32)> {
        let face = natural_usize(face, "face")?;
        let range = self.surface.ptex_faces(face).map_err(to_py)?;
        Ok((range.start, range.end - range.start))
    }

    /// Position and derivatives at points (ptex face, u, v); with `curvature`, the unit
    /// normal and mean, Gaussian and principal curvatures too. Derivatives are with respect
    /// to the ptex face's (u, v); orders above `derivatives` are left out.
    #[pyo3(signature = (faces, u, v, *, derivatives, curvature))]
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        faces: PyReadonlyArray1<'py, u32>,
        u: PyReadonlyArray1<'py, f64>,
        v: PyReadonlyArray1<'py, f64>,
        derivatives: &Bound<'py, PyAny>,
        curvature: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let derivatives = natural(derivatives, "derivatives", 3)? as u32;
        if curvature && derivatives < 2 {
            return Err(InvalidInput::new_err(
                "curvature needs derivatives ≥ 2 (it is made of the second derivatives)",
            ));
        }
        let points = self
            .surface
            .surface_points(faces.as_slice()?, u.as_slice()?, v.as_slice()?)
            .map_err(to_py)?;
        let surface = &self.surface;
        let evaluated = py.detach(|| surface.evaluate(&points)).map_err(to_py)?;
        let n = evaluated.len();
        let out = PyDict::new(py);
        let column = |pick: &dyn Fn(&surfkit::subdiv::Derivatives) -> [f64; 3]| {
            let flat: Vec<f64> = evaluated.iter().flat_map(pick).collect();
            flat.into_pyarray(py).reshape([n, 3])
        };
        type Pick = fn(&surfkit::subdiv::Derivatives) -> [f64; 3];
        let orders: [(u32, &str, Pick); 10] = [
            (0, "position", |d| d.position),
            (1, "du", |d| d.du),
            (1, "dv", |d| d.dv),
            (2, "duu", |d| d.duu),
            (2, "duv", |d| d.duv),
            (2, "dvv", |d| d.dvv),
            (3, "duuu", |d| d.duuu),
            (3, "duuv", |d| d.duuv),
            (3, "duvv", |d| d.duvv),
            (3, "dvvv", |d| d.dvvv),
        ];
        for (order, name, pick) in orders {
            if order <= derivatives {
                out.set_item(name, column(&pick)?)?;
            }
        }
        if curvature {
            let mut normals = Vec::with_capacity(3 * n);
            let mut values = [(); 4].map(|_| Vec::with_capacity(n));
            for (i, d) in evaluated.iter().enumerate() {
                let c = surfkit::subdiv::curvature(d).map_err(|e| {
                    TopologyError::new_err(format!(
                        "point {i} (ptex face {}, u {}, v {}): {e}",
                        points[i].ptex_face, points[i].u, points[i].v
                    ))
                })?;
                normals.extend(c.normal);
                for (slot, x) in values.iter_mut().zip([c.mean, c.gaussian, c.k1, c.k2]) {
                    slot.push(x);
                }
            }
            let normals: Bound<'py, PyArray2<f64>> = normals.into_pyarray(py).reshape([n, 3])?;
            out.set_item("normal", normals)?;
            let [mean, gaussian, k1, k2] = values;
            out.set_item("mean_curvature", mean.into_pyarray(py))?;
            out.set_item("gaussian_curvature", gaussian.into_pyarray(py))?;
            out.set_item("k1", k1.into_pyarray(py))?;
            out.set_item("k2", k2.into_pyarray(py))?;
        }
        Ok(out)
    }
}
