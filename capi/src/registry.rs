//! The accompanying test while a program builds a mesh (Liu et al. 2020 §3–4): facets are
//! registered one by one — every facet, also those a half-edge structure would refuse —
//! and a test point compares χ so far with what the model should have, whenever asked.

use std::ffi::c_int;

use surfkit::topology::ModelCompanion;

use crate::pointers::{clear, give, output, reference, slice, take};
use crate::status::{guard, Failure};

/// An opaque registry (free with [`surfkit_registry_free`]).
pub struct SurfkitRegistry {
    companion: ModelCompanion,
    /// Vertex ids must lie below this (the caller's vertex count): ids index the
    /// registry's arrays, so an absurd id must not allocate gigabytes.
    vertex_limit: u32,
    /// Input ids of the facets since the last verified point, as of the last test point.
    suspects: Vec<u32>,
}

/// V, E, F and χ of what has been registered (EAT-SA).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct SurfkitEatStatistics {
    pub vertices: usize,
    pub edges: usize,
    pub facets: usize,
    pub euler_characteristic: i64,
}

/// A test point's outcome; the facets added since the last verified point are listed by
/// [`surfkit_registry_suspects`].
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct SurfkitCheckpoint {
    pub verified: c_int,
    pub expected_euler_characteristic: i64,
    pub statistics: SurfkitEatStatistics,
    /// Facet count at the last verified point before this one.
    pub last_verified_facets: usize,
}

/// A registry for vertex ids `0 .. vertex_count` (raise it with
/// [`surfkit_registry_set_vertex_count`] as the model grows).
///
/// # Safety
/// `out` must be writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_registry_new(
    vertex_count: u32,
    out: *mut *mut SurfkitRegistry,
) -> c_int {
    guard(|| {
        clear(out, std::ptr::null_mut());
        give(
            output(out, "out")?,
            SurfkitRegistry {
                companion: ModelCompanion::new(),
                vertex_limit: vertex_count,
                suspects: Vec::new(),
            },
        );
        Ok(())
    })
}

/// Raises (or lowers) the bound on vertex ids.
///
/// # Safety
/// `registry` must be a live handle.
#[no_mangle]
pub unsafe extern "C" fn surfkit_registry_set_vertex_count(
    registry: *mut SurfkitRegistry,
    vertex_count: u32,
) -> c_int {
    guard(|| {
        registry
            .as_mut()
            .ok_or_else(|| Failure::invalid("registry is a null pointer"))?
            .vertex_limit = vertex_count;
        Ok(())
    })
}

/// Registers one facet (`corner_count` vertex ids, any arity ≥ 1); `input_id` is how the
/// caller names it in reports (a face handle's index, say). `facet` (may be null) receives
/// its position in the registry's Facet list, or `UINT32_MAX` when the call fails. The registry keeps an item per vertex id up to
/// the largest (20 bytes each): an id whose items would pass the memory limit
/// (`surfkit_set_max_memory`) is refused with `SURFKIT_RESOURCE_LIMIT`, naming the id and
/// the memory, and nothing is registered.
///
/// # Safety
/// `registry` must be a live handle; `corners` must hold `corner_count` ids.
#[no_mangle]
pub unsafe extern "C" fn surfkit_registry_add_facet(
    registry: *mut SurfkitRegistry,
    corners: *const u32,
    corner_count: usize,
    input_id: u32,
    facet: *mut u32,
) -> c_int {
    guard(|| {
        clear(facet, u32::MAX);
        let r = registry
            .as_mut()
            .ok_or_else(|| Failure::invalid("registry is a null pointer"))?;
        let corners = slice(corners, corner_count, "corners")?;
        if corners.is_empty() {
            return Err(Failure::invalid(format!("facet {input_id} has no corners")));
        }
        if let Some(&v) = corners.iter().find(|&&v| v >= r.vertex_limit) {
            return Err(Failure::invalid(format!(
                "facet {input_id} refers to vertex {v}, but the registry is for {} vertices \
                 (surfkit_registry_set_vertex_count raises it)",
                r.vertex_limit
            )));
        }
        let registered = r.companion.register(corners, input_id)?;
        if let Some(facet) = facet.as_mut() {
            *facet = registered;
        }
        Ok(())
    })
}

/// V, E, F and χ so far.
///
/// # Safety
/// `registry` must be a live handle; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_registry_statistics(
    registry: *const SurfkitRegistry,
    out: *mut SurfkitEatStatistics,
) -> c_int {
    guard(|| {
        clear(out, SurfkitEatStatistics::default());
        let s = reference(registry, "registry")?.companion.statistics();
        *output(out, "out")? = SurfkitEatStatistics {
            vertices: s.vertices,
            edges: s.edges,
            facets: s.facets,
            euler_characteristic: s.euler_characteristic,
        };
        Ok(())
    })
}

/// A test point: is χ of what has been registered `expected_euler_characteristic`?
///
/// # Safety
/// `registry` must be a live handle; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_registry_checkpoint(
    registry: *mut SurfkitRegistry,
    expected_euler_characteristic: i64,
    out: *mut SurfkitCheckpoint,
) -> c_int {
    guard(|| {
        clear(out, SurfkitCheckpoint::default());
        let out = output(out, "out")?;
        let r = registry
            .as_mut()
            .ok_or_else(|| Failure::invalid("registry is a null pointer"))?;
        let c = r.companion.checkpoint(expected_euler_characteristic);
        r.suspects = c.since_last_verified.iter().map(|f| f.input_id).collect();
        *out = SurfkitCheckpoint {
            verified: c.verified as c_int,
            expected_euler_characteristic,
            statistics: SurfkitEatStatistics {
                vertices: c.statistics.vertices,
                edges: c.statistics.edges,
                facets: c.statistics.facets,
                euler_characteristic: c.statistics.euler_characteristic,
            },
            last_verified_facets: c.last_verified_facets,
        };
        Ok(())
    })
}

/// The input ids of the facets added since the last verified point, as of the last test
/// point (empty when it was verified): where the paper's user looks for the flaw.
/// Borrowed: valid until the next call on the registry.
///
/// # Safety
/// `registry` must be a live handle; outputs writable.
#[no_mangle]
pub unsafe extern "C" fn surfkit_registry_suspects(
    registry: *const SurfkitRegistry,
    input_ids: *mut *const u32,
    count: *mut usize,
) -> c_int {
    guard(|| {
        clear(input_ids, std::ptr::null());
        clear(count, 0);
        let r = reference(registry, "registry")?;
        let (ids, n) = (output(input_ids, "input_ids")?, output(count, "count")?);
        *ids = r.suspects.as_ptr();
        *n = r.suspects.len();
        Ok(())
    })
}

/// Frees a registry (null is ignored).
///
/// # Safety
/// `registry` must be null or a handle not freed before.
#[no_mangle]
pub unsafe extern "C" fn surfkit_registry_free(registry: *mut SurfkitRegistry) {
    let _ = guard(|| {
        take(registry);
        Ok(())
    });
}
