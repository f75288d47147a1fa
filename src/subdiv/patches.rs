//! The limit surface as bicubic B-spline patches: OpenSubdiv's feature-adaptive
//! `Far::PatchTable` with `ENDCAP_BSPLINE_BASIS` end caps, in doubles.
//!
//! Every patch has 16 control points, each a fixed linear combination (a stencil) of the
//! control mesh's vertices. Refined vertices carry their stencil on the control vertices;
//! end-cap points carry theirs on earlier points (refined vertices), which keeps the table
//! linear in size around a vertex of high valence. Patches touching a boundary carry a boundary mask: OpenSubdiv
//! stores only the points on the surface's side and folds the missing "phantom" row or
//! column into the weights when it evaluates. [`PatchSurface::patch_weights`] reproduces
//! those phantom points (a boundary row `P₀ = 2 P₁ − P₂`, applied left, top, right, bottom
//! so that corners come out right — the transpose of Far's `BoundBasisBSpline`), so each
//! exported patch is an ordinary 16-point bicubic B-spline patch.
//!
//! Parameters are OpenSubdiv's ptex faces: a quad is one ptex face, an n-gon (n ≠ 4) is
//! split into n quads, each its own ptex face ([`PatchSurface::ptex_faces`]). A patch covers
//! the square `[u0, u0 + size] × [v0, v0 + size]` of its ptex face.

use std::collections::BTreeMap;

use rayon::prelude::*;
use std::ops::Range;

use crate::error::{Error, Result};
use crate::ffi::opensubdiv as ffi;
use crate::limits::MemoryBudget;
use crate::mesh::PolygonMesh;
use crate::subdiv::bspline::{eval_patch, Derivatives};
use crate::subdiv::topology::ControlMesh;
use crate::subdiv::SubdivOptions;

/// Options of [`limit_surface`].
#[derive(Debug, Clone, PartialEq)]
pub struct PatchOptions {
    /// Levels of feature-adaptive refinement around extraordinary vertices and creases
    /// (1..=10). Higher isolates irregular features into smaller end-cap patches: more
    /// patches, closer to the true limit surface near extraordinary vertices.
    pub max_isolation: u32,
    /// What the patch table may take. Where the refined vertices of `max_isolation` would
    /// pass it, the isolation stops at a lower level ([`PatchSurface::isolation`] says
    /// which); where even level 1 or the stencils would pass it, the build fails with
    /// [`Error::ResourceLimit`].
    pub memory: MemoryBudget,
    /// Stencil weights the table may hold: the work of building and evaluating it (about
    /// 0.7 s per 10 M as a whole `limit` command: 87 M weights took 6.4 s on this
    /// project's 2-core machine, 2026-11-25). Like `memory`, it lowers the
    /// isolation where the table would pass it (refined vertices count 16 weights each, the
    /// end caps are estimated before OpenSubdiv allocates them), and fails the build where
    /// even level 1 does. A mesh whose every vertex is extraordinary (a triangle mesh)
    /// reaches it first.
    pub max_stencil_weights: usize,
}

/// [`PatchOptions::max_stencil_weights`] by default: a 100k-triangle mesh (every vertex
/// extraordinary, 87 M weights at isolation 1) fits, in seconds.
pub const DEFAULT_MAX_STENCIL_WEIGHTS: usize = 100_000_000;

impl Default for PatchOptions {
    fn default() -> Self {
        PatchOptions {
            max_isolation: 4,
            memory: MemoryBudget::default(),
            max_stencil_weights: DEFAULT_MAX_STENCIL_WEIGHTS,
        }
    }
}

/// Bytes one stencil weight takes while the table is built: an index and a weight where the
/// table keeps them (the shim's composer, OpenSubdiv's local point table; not copied), and
/// as much again for OpenSubdiv's transient copy while it builds the end caps (measured: a
/// 100k-triangle grid at isolation 1, 87 M weights, peaked at 1.85 GB).
const BYTES_PER_STENCIL_WEIGHT: u64 = 2 * (4 + 8);

/// Bytes per refined vertex of OpenSubdiv's refiner and patch table and of the surface's
/// points and patches (measured: a 100k-triangle grid at isolation 4, 17.8 M refined points
/// and 185 M stencil weights, peaked at 11.3 GB).
const BYTES_PER_REFINED_POINT: u64 = 320;

/// One bicubic B-spline patch of the limit surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Patch {
    /// Ptex face the patch lies in.
    pub ptex_face: u32,
    /// Base (control mesh) face that ptex face belongs to.
    pub base_face: u32,
    /// Refinement level at which the patch was isolated.
    pub depth: u32,
    /// Bit 0: v = 0 edge on the boundary; bit 1: u = 1; bit 2: v = 1; bit 3: u = 0.
    pub boundary_mask: u8,
    /// A regular patch of the subdivision surface (exact); `false` for an end cap (a
    /// B-spline approximation around an extraordinary vertex).
    pub regular: bool,
    /// The patch's square in its ptex face: `[u0, u0 + size] × [v0, v0 + size]`.
    pub u0: f64,
    pub v0: f64,
    pub size: f64,
}

/// A point of the limit surface to evaluate: a ptex face and `(u, v) ∈ [0, 1]²` in it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    pub ptex_face: u32,
    pub u: f64,
    pub v: f64,
}

/// The limit surface of a control mesh as bicubic B-spline patches.
pub struct PatchSurface {
    control_points: Vec<[f64; 3]>,
    patches: Vec<Patch>,
    /// 16 patch-point ids per patch (OpenSubdiv's order; phantom slots unused).
    patch_points: Vec<i32>,
    /// Positions of all patch points (control vertices first, then stencil points).
    point_positions: Vec<[f64; 3]>,
    data: ffi::PatchData,
    /// Patches of each ptex face.
    patches_of_ptex: Vec<Vec<u32>>,
    table: ffi::PatchTable,
    isolation: u32,
}

/// Builds the limit surface of `mesh` with `options`' sharp features and rules.
///
/// Preconditions: those of [`crate::subdiv::refine_uniform`] (valid mesh, faces of ≥ 3
/// corners, creases on edges) and `1 ≤ max_isolation ≤ 10`. With
/// [`BoundaryInterpolation::None`](crate::subdiv::BoundaryInterpolation::None) boundary
/// faces get no patches.
///
/// # Errors
/// [`Error::InvalidInput`] for a failed precondition, [`Error::Ffi`] when OpenSubdiv
/// refuses the topology or builds something other than B-spline patches.
pub fn limit_surface(
    mesh: &PolygonMesh,
    options: &SubdivOptions,
    patch_options: &PatchOptions,
) -> Result<PatchSurface> {
    if !(1..=10).contains(&patch_options.max_isolation) {
        return Err(Error::InvalidInput(format!(
            "max_isolation {} must be in 1..=10",
            patch_options.max_isolation
        )));
    }
    let control = ControlMesh::new(mesh, options, false)?;
    let topology = control.topology();
    // Half of the budget for the refined points, half for the stencils.
    let half = MemoryBudget::bytes(patch_options.memory.get() / 2);
    let work = patch_options.max_stencil_weights;
    let max_points = usize::try_from(half.items(BYTES_PER_REFINED_POINT))
        .unwrap_or(usize::MAX)
        .min(work / 16);
    let max_weights = usize::try_from(half.items(BYTES_PER_STENCIL_WEIGHT))
        .unwrap_or(usize::MAX)
        .min(work);
    // The shim stops refining where the points would pass their limit; where the stencils
    // do, try lower levels (fewer levels do not always mean fewer weights: end caps at a low
    // level carry more than the regular patches of a higher one).
    let mut isolation = patch_options.max_isolation;
    let table = loop {
        match ffi::PatchTable::new(&topology, isolation as i32, max_points, max_weights)? {
            Some(table) => break table,
            None if isolation > 1 => isolation -= 1,
            None => {
                let what = format!(
                    "the limit surface of {} vertices and {} faces",
                    mesh.vertex_count(),
                    mesh.face_count()
                );
                let advice = format!(
                    "at no isolation level do its refinement and stencils fit in {max_points} \
                     refined vertices and {max_weights} stencil weights"
                );
                // Name the bound that bit: the work bound where it is below the memory's.
                return Err(if max_weights == work || max_points == work / 16 {
                    Error::WorkLimit {
                        what,
                        limit: format!(
                            "{work} stencil weights, the bound on a limit surface's work \
                             (--max-stencils)"
                        ),
                        advice,
                    }
                } else {
                    Error::ResourceLimit {
                        what,
                        limit: patch_options.memory.get(),
                        advice,
                    }
                });
            }
        }
    };
    let isolation = table.isolation();
    let mut data = table.data(control.face_count())?;
    let ncv = data.num_control_vertices;
    let stencils = table.stencils();
    if ncv != mesh.vertex_count() || stencils.len() != data.num_patch_points - ncv {
        return Err(Error::Ffi {
            library: "OpenSubdiv",
            message: "patch table counts disagree with the control mesh".into(),
        });
    }
    // Indices from the shim are checked once here, so that evaluation can index freely.
    let points_ok = data
        .patch_points
        .iter()
        .all(|&i| i < data.num_patch_points as i32);
    // A stencil refers to control vertices or to points before its own.
    let stencils_ok = stencils.well_formed(ncv);
    let ptex_ok = data
        .ptex_face
        .iter()
        .all(|&p| p >= 0 && (p as usize) < data.num_ptex_faces)
        && data
            .ptex_of_face
            .windows(2)
            .all(|w| 0 <= w[0] && w[0] <= w[1])
        && data.ptex_of_face.last().map(|&o| o as usize) == Some(data.num_ptex_faces);
    if !(points_ok && stencils_ok && ptex_ok) {
        return Err(Error::Ffi {
            library: "OpenSubdiv",
            message: "patch table indices out of range".into(),
        });
    }
    let face_of_ptex = {
        let mut out = vec![0u32; data.num_ptex_faces];
        for f in 0..control.face_count() {
            for p in data.ptex_of_face[f]..data.ptex_of_face[f + 1] {
                out[p as usize] = f as u32;
            }
        }
        out
    };
    let np = data.ptex_face.len();
    let mut patches = Vec::with_capacity(np);
    let mut patches_of_ptex = vec![Vec::new(); data.num_ptex_faces];
    for i in 0..np {
        let ptex = data.ptex_face[i] as u32;
        patches.push(Patch {
            ptex_face: ptex,
            base_face: face_of_ptex[ptex as usize],
            depth: data.depth[i] as u32,
            boundary_mask: data.boundary_mask[i] as u8,
            regular: data.is_regular[i] != 0,
            u0: data.u0[i],
            v0: data.v0[i],
            size: data.size[i],
        });
        patches_of_ptex[ptex as usize].push(i as u32);
    }
    let mut surface = PatchSurface {
        control_points: mesh.positions.clone(),
        patches,
        patch_points: std::mem::take(&mut data.patch_points),
        point_positions: Vec::new(),
        data,
        patches_of_ptex,
        table,
        isolation,
    };
    surface.update_points()?;
    Ok(surface)
}

/// Applies Far's boundary-mask rule to 16 values (points or weight rows): phantom row or
/// column `P₀ = 2 P₁ − P₂`, in the order left, top, right, bottom.
fn fill_phantoms<T: Clone>(mask: u8, p: &mut [T; 16], affine: impl Fn(&T, &T) -> T) {
    if mask & 8 != 0 {
        for r in (0..16).step_by(4) {
            p[r] = affine(&p[r + 1], &p[r + 2]);
        }
    }
    if mask & 4 != 0 {
        for c in 0..4 {
            p[12 + c] = affine(&p[8 + c], &p[4 + c]);
        }
    }
    if mask & 2 != 0 {
        for r in (0..16).step_by(4) {
            p[r + 3] = affine(&p[r + 2], &p[r + 1]);
        }
    }
    if mask & 1 != 0 {
        for c in 0..4 {
            p[c] = affine(&p[4 + c], &p[8 + c]);
        }
    }
}

impl PatchSurface {
    fn update_points(&mut self) -> Result<()> {
        let ncv = self.data.num_control_vertices;
        let d = &self.data;
        let stencils = self.table.stencils();
        let mut pts = self.control_points.clone();
        pts.reserve(d.num_patch_points - ncv);
        for s in 0..d.num_patch_points - ncv {
            let (indices, weights) = stencils.get(s);
            let mut p = [0.0; 3];
            for (&i, &w) in indices.iter().zip(weights) {
                let q = pts[i as usize];
                for k in 0..3 {
                    p[k] += w * q[k];
                }
            }
            pts.push(p);
        }
        self.point_positions = pts;
        Ok(())
    }

    /// The isolation level the table was built with: `max_isolation`, or lower when the
    /// memory budget did not allow it.
    pub fn isolation(&self) -> u32 {
        self.isolation
    }

    /// The patches, in OpenSubdiv's order.
    pub fn patches(&self) -> &[Patch] {
        &self.patches
    }

    /// The control mesh's vertex positions the surface is built on.
    pub fn control_points(&self) -> &[[f64; 3]] {
        &self.control_points
    }

    /// Moves the control vertices (same topology): patches follow through their stencils.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] if the count differs or a coordinate is not finite.
    pub fn set_control_points(&mut self, positions: &[[f64; 3]]) -> Result<()> {
        if positions.len() != self.control_points.len() {
            return Err(Error::InvalidInput(format!(
                "{} control points given, the surface has {}",
                positions.len(),
                self.control_points.len()
            )));
        }
        if let Some(v) = positions
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(Error::InvalidInput(format!(
                "control point {v} is not finite"
            )));
        }
        self.control_points = positions.to_vec();
        self.update_points()
    }

    /// The ptex faces of base face `f`: one for a quad, n for an n-gon.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] if `f` is not a face.
    pub fn ptex_faces(&self, f: usize) -> Result<Range<u32>> {
        let o = &self.data.ptex_of_face;
        if f + 1 >= o.len() {
            return Err(Error::InvalidInput(format!("face {f} does not exist")));
        }
        Ok(o[f] as u32..o[f + 1] as u32)
    }

    pub fn ptex_face_count(&self) -> usize {
        self.data.num_ptex_faces
    }

    /// The patches of ptex face `ptex` (none for a face without limit surface).
    pub fn patches_of_ptex_face(&self, ptex: u32) -> &[u32] {
        self.patches_of_ptex
            .get(ptex as usize)
            .map_or(&[], |v| v.as_slice())
    }

    /// The 16 control points of patch `p` as weights of control vertices: entry `k` lists
    /// `(vertex, weight)` pairs whose weighted sum is control point `k` (row-major, u
    /// fastest), phantom points included. This is also the derivative of the patch's
    /// control points with respect to the control vertices.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] if `p` is not a patch.
    pub fn patch_weights(&self, p: usize) -> Result<[Vec<(u32, f64)>; 16]> {
        let patch = self.patch(p)?;
        let ncv = self.data.num_control_vertices;
        let stencils = self.table.stencils();
        let mut rows: [Vec<(u32, f64)>; 16] = std::array::from_fn(|_| Vec::new());
        let phantom = phantom_slots(patch.boundary_mask);
        for (k, row) in rows.iter_mut().enumerate() {
            if phantom[k] {
                continue;
            }
            // Expand through points with stencils down to control vertices, latest point
            // first: stencils refer to earlier points only, so each point is expanded once
            // with its whole weight.
            let mut pending = BTreeMap::from([(self.patch_points[16 * p + k] as usize, 1.0)]);
            while let Some((id, w)) = pending.pop_last() {
                if id < ncv {
                    row.push((id as u32, w));
                    continue;
                }
                let (indices, weights) = stencils.get(id - ncv);
                for (&i, &sw) in indices.iter().zip(weights) {
                    *pending.entry(i as usize).or_insert(0.0) += w * sw;
                }
            }
            row.reverse();
        }
        let mut out = rows;
        fill_phantoms(patch.boundary_mask, &mut out, |a, b| {
            let mut v: Vec<(u32, f64)> = a.iter().map(|&(i, w)| (i, 2.0 * w)).collect();
            v.extend(b.iter().map(|&(i, w)| (i, -w)));
            merge(v)
        });
        Ok(out)
    }

    fn patch(&self, p: usize) -> Result<&Patch> {
        self.patches
            .get(p)
            .ok_or_else(|| Error::InvalidInput(format!("patch {p} does not exist")))
    }

    /// The 16 control points of patch `p` (phantoms reproduced): an exact 16-point bicubic
    /// B-spline patch over its square.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] if `p` is not a patch.
    pub fn patch_control_points(&self, p: usize) -> Result<[[f64; 3]; 16]> {
        let patch = self.patch(p)?;
        let phantom = phantom_slots(patch.boundary_mask);
        let mut pts: [[f64; 3]; 16] = std::array::from_fn(|k| {
            if phantom[k] {
                [0.0; 3]
            } else {
                self.point_positions[self.patch_points[16 * p + k] as usize]
            }
        });
        fill_phantoms(patch.boundary_mask, &mut pts, |a, b| {
            [2.0 * a[0] - b[0], 2.0 * a[1] - b[1], 2.0 * a[2] - b[2]]
        });
        Ok(pts)
    }

    /// Points given as three parallel arrays (ptex face, u, v), checked one by one.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for arrays of different lengths, or naming the first point
    /// whose ptex face does not exist or whose `(u, v)` is outside `[0, 1]²`.
    pub fn surface_points(&self, ptex: &[u32], u: &[f64], v: &[f64]) -> Result<Vec<SurfacePoint>> {
        if ptex.len() != u.len() || u.len() != v.len() {
            return Err(Error::InvalidInput(format!(
                "ptex faces, u and v must have one entry per point: {}, {} and {}",
                ptex.len(),
                u.len(),
                v.len()
            )));
        }
        let total = self.ptex_face_count();
        (0..ptex.len())
            .map(|i| {
                if ptex[i] as usize >= total {
                    return Err(Error::InvalidInput(format!(
                        "point {i}: ptex face {} out of range (the surface has {total})",
                        ptex[i]
                    )));
                }
                if !((0.0..=1.0).contains(&u[i]) && (0.0..=1.0).contains(&v[i])) {
                    return Err(Error::InvalidInput(format!(
                        "point {i}: (u, v) = ({}, {}) is outside [0, 1]²",
                        u[i], v[i]
                    )));
                }
                Ok(SurfacePoint {
                    ptex_face: ptex[i],
                    u: u[i],
                    v: v[i],
                })
            })
            .collect()
    }

    /// The patch holding `point` and the point's coordinates `(s, t)` in that patch's unit
    /// square.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when the ptex face does not exist, `(u, v)` is outside
    /// `[0, 1]²` or not finite, or the face has no limit surface (a boundary face under
    /// `BoundaryInterpolation::None`).
    pub fn locate(&self, point: &SurfacePoint) -> Result<(usize, f64, f64)> {
        let SurfacePoint { ptex_face, u, v } = *point;
        if ptex_face as usize >= self.data.num_ptex_faces {
            return Err(Error::InvalidInput(format!(
                "ptex face {ptex_face} does not exist"
            )));
        }
        if !(0.0..=1.0).contains(&u) || !(0.0..=1.0).contains(&v) {
            return Err(Error::InvalidInput(format!(
                "(u, v) = ({u}, {v}) is outside the unit square of ptex face {ptex_face}"
            )));
        }
        for &p in self.patches_of_ptex_face(ptex_face) {
            let q = &self.patches[p as usize];
            if u >= q.u0 && u <= q.u0 + q.size && v >= q.v0 && v <= q.v0 + q.size {
                return Ok((p as usize, (u - q.u0) / q.size, (v - q.v0) / q.size));
            }
        }
        Err(Error::InvalidInput(format!(
            "ptex face {ptex_face} has no limit surface at ({u}, {v}) (a boundary face with \
             BoundaryInterpolation::None?)"
        )))
    }

    /// Limit position and derivatives up to third order at each point, with respect to the
    /// ptex face's (u, v). Orders 0–2 come from OpenSubdiv's `PatchTable::EvaluateBasis`
    /// (one call for all points); third order from the bicubic basis of the exported patch.
    /// Under an n-gon's sub-faces OpenSubdiv differentiates with respect to half-scale
    /// parameters (it scales by 2^depth whatever the face); the result is rescaled to the
    /// ptex face's (u, v), as finite differences confirm.
    ///
    /// # Errors
    /// Those of [`PatchSurface::locate`]; [`Error::Ffi`] if OpenSubdiv fails.
    pub fn evaluate(&self, points: &[SurfacePoint]) -> Result<Vec<Derivatives>> {
        // Chunks on rayon's threads: the table is read-only, and millions of samples (a
        // limit map of a large mesh) are the bulk of `surfkit limit`.
        const CHUNK: usize = 4096;
        if points.len() <= CHUNK {
            return self.evaluate_serial(points);
        }
        let parts: Vec<Vec<Derivatives>> = points
            .par_chunks(CHUNK)
            .map(|chunk| self.evaluate_serial(chunk))
            .collect::<Result<_>>()?;
        Ok(parts.into_iter().flatten().collect())
    }

    fn evaluate_serial(&self, points: &[SurfacePoint]) -> Result<Vec<Derivatives>> {
        let located: Vec<(usize, f64, f64)> = points
            .iter()
            .map(|p| self.locate(p))
            .collect::<Result<_>>()?;
        let patch: Vec<i32> = located.iter().map(|l| l.0 as i32).collect();
        let u: Vec<f64> = points.iter().map(|p| p.u).collect();
        let v: Vec<f64> = points.iter().map(|p| p.v).collect();
        let w = self.table.evaluate_basis(&patch, &u, &v)?;
        let mut out = Vec::with_capacity(points.len());
        for (i, &(p, s, t)) in located.iter().enumerate() {
            let mut d = self.evaluate_in_patch(p, s, t)?;
            let mut order = [[0.0; 3]; 6];
            for (k, acc) in order.iter_mut().enumerate() {
                for c in 0..16 {
                    let weight = w[96 * i + 16 * k + c];
                    let id = self.patch_points[16 * p + c];
                    if weight != 0.0 && id >= 0 {
                        let q = self.point_positions[id as usize];
                        for x in 0..3 {
                            acc[x] += weight * q[x];
                        }
                    }
                }
            }
            // EvaluateBasis scales derivatives by 2^depth, which is 1 / size except under an
            // n-gon's sub-face (size = 2^(1 − depth)): there it differentiates with respect
            // to half-scale parameters. Rescale to the ptex face's (u, v).
            let patch = &self.patches[p];
            let c = 1.0 / (patch.size * f64::from(1u32 << patch.depth));
            for (k, x) in order.iter_mut().enumerate().skip(1) {
                let f = if k < 3 { c } else { c * c };
                x.iter_mut().for_each(|e| *e *= f);
            }
            [d.position, d.du, d.dv, d.duu, d.duv, d.dvv] = order;
            out.push(d);
        }
        Ok(out)
    }

    /// Position and derivatives up to third order from the exported 16-point patch alone
    /// (pure Rust), with respect to the ptex face's (u, v), at `(s, t)` of patch `p`'s
    /// unit square.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] if `p` is not a patch or `(s, t)` is not in `[0, 1]²`.
    pub fn evaluate_in_patch(&self, p: usize, s: f64, t: f64) -> Result<Derivatives> {
        if !(0.0..=1.0).contains(&s) || !(0.0..=1.0).contains(&t) {
            return Err(Error::InvalidInput(format!(
                "(s, t) = ({s}, {t}) is outside the unit square"
            )));
        }
        let size = self.patch(p)?.size;
        let mut d = eval_patch(&self.patch_control_points(p)?, s, t);
        // Chain rule: u = u0 + size s, so ∂/∂u = (1 / size) ∂/∂s.
        let scale = |x: &mut [f64; 3], order: i32| {
            let f = size.powi(-order);
            x.iter_mut().for_each(|c| *c *= f);
        };
        scale(&mut d.du, 1);
        scale(&mut d.dv, 1);
        scale(&mut d.duu, 2);
        scale(&mut d.duv, 2);
        scale(&mut d.dvv, 2);
        scale(&mut d.duuu, 3);
        scale(&mut d.duuv, 3);
        scale(&mut d.duvv, 3);
        scale(&mut d.dvvv, 3);
        Ok(d)
    }
}

/// Slots of a 4 × 4 patch that a boundary mask marks as phantom.
fn phantom_slots(mask: u8) -> [bool; 16] {
    std::array::from_fn(|k| {
        let (r, c) = (k / 4, k % 4);
        (mask & 1 != 0 && r == 0)
            || (mask & 2 != 0 && c == 3)
            || (mask & 4 != 0 && r == 3)
            || (mask & 8 != 0 && c == 0)
    })
}

/// Sums the weights of repeated vertices.
fn merge(mut v: Vec<(u32, f64)>) -> Vec<(u32, f64)> {
    v.sort_by_key(|e| e.0);
    let mut out: Vec<(u32, f64)> = Vec::with_capacity(v.len());
    for (i, w) in v {
        match out.last_mut() {
            Some(last) if last.0 == i => last.1 += w,
            _ => out.push((i, w)),
        }
    }
    out
}
