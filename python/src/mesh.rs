//! `Mesh`: a polygon mesh (positions f64, faces as offsets + indices) made from numpy arrays
//! or read from OBJ/PLY/OFF, checked before any algorithm sees it.

use std::path::PathBuf;

use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use surfkit::mesh::io::{read_with, write, ReadOptions, WriteOptions};
use surfkit::mesh::PolygonMesh;

use crate::errors::{to_py, InvalidInput};

/// A polygon mesh owned by surfkit: vertices (n, 3) float64, faces as `face_indices`
/// (uint32) cut by `face_offsets` (m + 1 entries, from 0); polygons of any arity, nothing
/// re-indexed or merged.
#[pyclass(module = "surfkit._surfkit", name = "Mesh", frozen)]
pub struct Mesh {
    pub(crate) mesh: PolygonMesh,
}

#[pymethods]
impl Mesh {
    /// `Mesh(vertices, faces)`: `vertices` (n, 3) numbers, `faces` an (m, k) integer array,
    /// a list of polygons of any arity, or an `(indices, offsets)` pair of 1-d arrays
    /// (`surfkit._arrays.mesh_arrays` brings each to uint32); raises `InvalidInput` naming
    /// the face or vertex at fault.
    #[new]
    fn new(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let arrays = py
            .import("surfkit._arrays")?
            .getattr("mesh_arrays")?
            .call1((vertices, faces))?;
        let (v, indices, offsets): (
            PyReadonlyArray2<'_, f64>,
            PyReadonlyArray1<'_, u32>,
            PyReadonlyArray1<'_, u32>,
        ) = arrays.extract()?;
        Self::from_arrays(v, indices, offsets)
    }

    /// A mesh from a `trimesh.Trimesh` (its vertices and triangles, as trimesh holds them).
    #[classmethod]
    fn from_trimesh(
        cls: &Bound<'_, pyo3::types::PyType>,
        mesh: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        Ok(cls
            .call1((mesh.getattr("vertices")?, mesh.getattr("faces")?))?
            .unbind())
    }

    /// A mesh from a `pymeshlab.Mesh` (its vertex and face matrices).
    #[classmethod]
    fn from_pymeshlab(
        cls: &Bound<'_, pyo3::types::PyType>,
        mesh: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        Ok(cls
            .call1((
                mesh.call_method0("vertex_matrix")?,
                mesh.call_method0("face_matrix")?,
            ))?
            .unbind())
    }

    /// The vertex positions, (n, 3) float64 (a copy).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let flat: Vec<f64> = self.mesh.positions.iter().flatten().copied().collect();
        let n = self.mesh.positions.len();
        flat.into_pyarray(py).reshape([n, 3]).expect("n × 3 values")
    }

    /// The corners of every face, concatenated (uint32, a copy).
    #[getter]
    fn face_indices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u32>> {
        self.mesh.face_indices.clone().into_pyarray(py)
    }

    /// Face f is `face_indices[face_offsets[f]:face_offsets[f + 1]]` (uint32, a copy).
    #[getter]
    fn face_offsets<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u32>> {
        self.mesh.face_offsets.clone().into_pyarray(py)
    }

    #[getter]
    fn vertex_count(&self) -> usize {
        self.mesh.vertex_count()
    }

    #[getter]
    fn face_count(&self) -> usize {
        self.mesh.face_count()
    }

    /// Writes the mesh (.obj, .ply, .off or binary .stl by the extension), never half-written.
    fn write(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let mesh = &self.mesh;
        py.detach(|| write(&path, mesh, &WriteOptions::default()))
            .map_err(to_py)
    }

    fn __repr__(&self) -> String {
        format!(
            "surfkit.Mesh({} vertices, {} faces)",
            self.mesh.vertex_count(),
            self.mesh.face_count()
        )
    }
}

impl Mesh {
    /// A checked mesh from positions (n, 3), corner indices and face offsets.
    fn from_arrays(
        vertices: PyReadonlyArray2<'_, f64>,
        face_indices: PyReadonlyArray1<'_, u32>,
        face_offsets: PyReadonlyArray1<'_, u32>,
    ) -> PyResult<Self> {
        let v = vertices.as_array();
        if v.ncols() != 3 {
            return Err(InvalidInput::new_err(format!(
                "vertices must have shape (n, 3), not {:?}",
                v.shape()
            )));
        }
        let mesh = PolygonMesh {
            positions: v.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect(),
            face_indices: face_indices.as_array().iter().copied().collect(),
            face_offsets: face_offsets.as_array().iter().copied().collect(),
            ..Default::default()
        };
        if mesh.face_offsets.is_empty() {
            return Err(InvalidInput::new_err(
                "face_offsets must hold at least one entry (0)",
            ));
        }
        mesh.validate().map_err(to_py)?;
        Ok(Mesh { mesh })
    }
}

/// Reads an OBJ, PLY, OFF or STL file as the CLI's `eat` and the C door do (`InvalidInput` names
/// the line or element of a malformed file): degenerate faces (fewer than 3 corners, a
/// repeated vertex) are kept, for `eat` to count them as flaws.
#[pyfunction]
pub fn read_mesh(py: Python<'_>, path: PathBuf) -> PyResult<Mesh> {
    let options = ReadOptions {
        keep_degenerate: true,
    };
    let mesh = py.detach(|| read_with(&path, &options)).map_err(to_py)?;
    Ok(Mesh { mesh })
}
