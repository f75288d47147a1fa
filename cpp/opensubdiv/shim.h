/* surfkit's plain-C shim over OpenSubdiv (Far). Opaque handles, POD structs of counts and
 * pointers, an int status (0 = success) plus an error message that the caller frees once
 * with surfkit_osd_free_message. Every function catches all C++ exceptions. bindgen reads
 * this header only.
 *
 * Bulk data crosses in one call per array: the caller first creates a handle (which reports
 * the counts), allocates arrays of those sizes and then copies everything out at once. */
#ifndef SURFKIT_OSD_SHIM_H
#define SURFKIT_OSD_SHIM_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* OpenSubdiv's version as major*10000 + minor*100 + patch (e.g. 30500). */
int surfkit_osd_version(void);

/* Refines a cube once (Catmull–Clark, uniform) and checks the refined counts: a health
 * check that the library links and runs. Returns 0, or non-zero with *error set. */
int surfkit_osd_self_test(char** error);

/* Frees a message returned by the shim (NULL is allowed). */
void surfkit_osd_free_message(char* message);

/* A control mesh for Catmull–Clark (Sdc::SCHEME_CATMARK) with its sharp features and
 * options. Arrays are borrowed for the duration of the call only. The option fields hold
 * the integer values of OpenSubdiv's Sdc::Options enums. */
typedef struct surfkit_osd_topology {
  int num_vertices;
  int num_faces;
  const int* verts_per_face;    /* num_faces */
  const int* face_vertices;     /* sum of verts_per_face */
  int num_creases;
  const int* crease_vertex_pairs; /* 2 * num_creases */
  const float* crease_sharpness;  /* num_creases */
  int num_corners;
  const int* corner_vertices;     /* num_corners */
  const float* corner_sharpness;  /* num_corners */
  /* Face-varying channel (UVs): num_fvar_values == 0 means none; otherwise fvar_indices
   * runs parallel to face_vertices. */
  int num_fvar_values;
  const int* fvar_indices;
  int vtx_boundary_interpolation; /* Sdc::Options::VtxBoundaryInterpolation */
  int fvar_linear_interpolation;  /* Sdc::Options::FVarLinearInterpolation */
  int creasing_method;            /* Sdc::Options::CreasingMethod */
  int triangle_subdivision;       /* Sdc::Options::TriangleSubdivision */
} surfkit_osd_topology;

/* ---- Uniform refinement ---------------------------------------------------------------- */

typedef struct surfkit_osd_uniform surfkit_osd_uniform;

typedef struct surfkit_osd_uniform_counts {
  int num_vertices;    /* vertices of the last level */
  int num_faces;       /* quads of the last level */
  int num_fvar_values; /* face-varying values of the last level (0 without a channel) */
} surfkit_osd_uniform_counts;

/* Builds the refiner and refines uniformly `levels` times (1..=10); reports the counts of
 * the last level. On success *out owns the refiner; destroy it with
 * surfkit_osd_uniform_destroy. */
int surfkit_osd_uniform_create(const surfkit_osd_topology* topology, int levels,
                               surfkit_osd_uniform** out, surfkit_osd_uniform_counts* counts,
                               char** error);

/* Interpolates positions (3 doubles per control vertex) and, with a face-varying channel,
 * its values (2 doubles per value) down to the last level, writing straight into the
 * caller's arrays sized from the counts: out_positions (3 per vertex), out_face_vertices
 * (4 per face), out_fvar_values (2 per value) and out_fvar_indices (4 per face); the fvar
 * pointers may be NULL without a channel. */
int surfkit_osd_uniform_copy(const surfkit_osd_uniform* refined, const double* positions,
                             const double* fvar_values, double* out_positions,
                             int* out_face_vertices, double* out_fvar_values,
                             int* out_fvar_indices, char** error);

void surfkit_osd_uniform_destroy(surfkit_osd_uniform* refined);

/* ---- Adaptive patch table (B-spline end caps) ------------------------------------------ */

typedef struct surfkit_osd_patches surfkit_osd_patches;

typedef struct surfkit_osd_patch_counts {
  int num_patches;
  int num_ptex_faces;        /* quads count once, an n-gon n times (Far::PtexIndices) */
  int num_control_vertices;  /* vertices of the control mesh */
  int num_patch_points;      /* size of the point index space of patch_points (all levels +
                                local points); indices >= num_control_vertices have stencils */
  int num_stencil_weights;   /* total entries of the stencils */
  int isolation;             /* the isolation level used (<= max_isolation, see the limits) */
} surfkit_osd_patch_counts;

/* What a patch table may hold: refined vertices (all levels) and stencil entries. */
typedef struct surfkit_osd_patch_limits {
  size_t max_refined_points;
  size_t max_stencil_weights;
} surfkit_osd_patch_limits;

/* Arrays the caller allocates from the counts (every pointer required). */
typedef struct surfkit_osd_patch_arrays {
  int* patch_points;     /* 16 per patch, row-major 4x4 (u fastest), into the point space */
  int* ptex_face;        /* per patch */
  int* depth;            /* per patch: refinement level of the patch */
  int* boundary_mask;    /* per patch: bit 0 v=0, bit 1 u=1, bit 2 v=1, bit 3 u=0 */
  int* is_regular;       /* per patch: 1 regular B-spline patch, 0 end cap */
  double* u0;            /* per patch: lower-left corner of its square in the ptex face */
  double* v0;
  double* size;          /* per patch: side length of its square */
  int* ptex_of_face;     /* num_faces + 1 offsets: ptex faces of base face f */
} surfkit_osd_patch_arrays;

/* Refines adaptively up to max_isolation (1..=10), lower where more levels would pass
 * limits->max_refined_points (counts->isolation says which), and builds the patch table with
 * ENDCAP_BSPLINE_BASIS end caps in double precision, plus the stencils of every patch point
 * beyond the control vertices (see stencil_indices). Returns 3 (nothing kept) when even
 * level 1 passes max_refined_points or the stencils would pass max_stencil_weights (the
 * end caps' are bounded before Far::PatchTableFactory allocates them). */
int surfkit_osd_patches_create(const surfkit_osd_topology* topology, int max_isolation,
                               const surfkit_osd_patch_limits* limits,
                               surfkit_osd_patches** out, surfkit_osd_patch_counts* counts,
                               char** error);

int surfkit_osd_patches_copy(const surfkit_osd_patches* patches,
                             const surfkit_osd_patch_arrays* arrays, char** error);

/* The stencils of the patch points beyond the control vertices, where the table keeps them
 * (valid while it lives; not copied: they are most of its memory). The refined points'
 * first, stencil k at [refined_offsets[k], refined_offsets[k + 1]) of refined_indices and
 * refined_weights, on control vertices and earlier points; then the end caps' local points',
 * stencil k at [local_offsets[k], local_offsets[k] + local_sizes[k]) of local_indices and
 * local_weights, on control vertices and refined points. Pointers of empty arrays may be
 * null. */
typedef struct surfkit_osd_stencils {
  size_t refined_count;
  const size_t* refined_offsets; /* refined_count + 1 */
  const int* refined_indices;    /* refined_offsets[refined_count] */
  const double* refined_weights;
  size_t local_count;
  const int* local_offsets;      /* local_count */
  const int* local_sizes;        /* local_count */
  size_t local_entries;          /* entries of local_indices and local_weights */
  const int* local_indices;
  const double* local_weights;
} surfkit_osd_stencils;

int surfkit_osd_patches_stencils(const surfkit_osd_patches* patches, surfkit_osd_stencils* out,
                                 char** error);

/* OpenSubdiv's Far::PatchTable::EvaluateBasis for n points (patch index, u, v in the
 * patch's ptex face): writes 6 * 16 weights per point in the order P, Du, Dv, Duu, Duv,
 * Dvv (weights of the 16 patch points, boundary mask applied). */
int surfkit_osd_patches_evaluate_basis(const surfkit_osd_patches* patches, int n,
                                       const int* patch, const double* u, const double* v,
                                       double* weights, char** error);

void surfkit_osd_patches_destroy(surfkit_osd_patches* patches);

#ifdef __cplusplus
}
#endif

#endif
