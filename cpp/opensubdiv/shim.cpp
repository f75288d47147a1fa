// Implementation of the OpenSubdiv shim (see shim.h).
#include "shim.h"
#include "stencil_composer.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include <memory>
#include <mutex>
#include <vector>

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <opensubdiv/version.h>

using namespace OpenSubdiv;

namespace {

char* copy_message(const std::string& s) {
  char* out = static_cast<char*>(std::malloc(s.size() + 1));
  if (out) std::memcpy(out, s.c_str(), s.size() + 1);
  return out;
}

// OpenSubdiv reports topology problems through a global callback; surfkit keeps the last
// message so a failing factory call can say why.
thread_local std::string last_osd_error;
void on_osd_error(Far::ErrorType, const char* message) { last_osd_error = message ? message : ""; }
void on_osd_warning(const char* message) { last_osd_error = message ? message : ""; }

// Once per process: calls may come from several threads at a time.
void install_callbacks() {
  static std::once_flag once;
  std::call_once(once, [] {
    Far::SetErrorCallback(on_osd_error);
    Far::SetWarningCallback(on_osd_warning);
  });
}

template <class F>
int guarded(char** error, F&& body) {
  try {
    install_callbacks();
    last_osd_error.clear();
    std::string msg = body();
    if (msg.empty()) return 0;
    if (error) *error = copy_message(msg);
    return 1;
  } catch (const std::exception& e) {
    if (error) *error = copy_message(std::string("OpenSubdiv: ") + e.what());
    return 2;
  } catch (...) {
    if (error) *error = copy_message("OpenSubdiv: unknown C++ exception");
    return 2;
  }
}

}  // namespace

extern "C" int surfkit_osd_version(void) { return OPENSUBDIV_VERSION_NUMBER; }

extern "C" int surfkit_osd_self_test(char** error) {
  return guarded(error, []() -> std::string {
    static const int verts_per_face[6] = {4, 4, 4, 4, 4, 4};
    static const int indices[24] = {0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6,
                                    6, 7, 1, 0, 1, 7, 5, 3, 6, 0, 2, 4};
    Far::TopologyDescriptor desc;
    desc.numVertices = 8;
    desc.numFaces = 6;
    desc.numVertsPerFace = verts_per_face;
    desc.vertIndicesPerFace = indices;
    typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;
    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    Far::TopologyRefiner* refiner =
        Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc));
    if (!refiner) return "TopologyRefinerFactory failed: " + last_osd_error;
    refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(1));
    int nv = refiner->GetLevel(1).GetNumVertices();
    int nf = refiner->GetLevel(1).GetNumFaces();
    delete refiner;
    if (nv != 26 || nf != 24)
      return "cube refined to " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
             " faces, expected 26 and 24";
    return "";
  });
}

extern "C" void surfkit_osd_free_message(char* message) { std::free(message); }

// ---- Topology ------------------------------------------------------------------------------

namespace {

typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> RefinerFactory;

// Builds a refiner from the C topology; the descriptor only borrows the arrays.
std::unique_ptr<Far::TopologyRefiner> make_refiner(const surfkit_osd_topology* t,
                                                   std::string& why) {
  if (!t || t->num_vertices < 0 || t->num_faces < 0 || (t->num_faces > 0 &&
      (!t->verts_per_face || !t->face_vertices))) {
    why = "topology: missing or negative counts/arrays";
    return nullptr;
  }
  if (t->vtx_boundary_interpolation < 0 || t->vtx_boundary_interpolation > 2 ||
      t->fvar_linear_interpolation < 0 || t->fvar_linear_interpolation > 5 ||
      t->creasing_method < 0 || t->creasing_method > 1 || t->triangle_subdivision < 0 ||
      t->triangle_subdivision > 1) {
    why = "topology: an option is out of the range of OpenSubdiv's Sdc::Options enums";
    return nullptr;
  }
  Far::TopologyDescriptor desc;
  desc.numVertices = t->num_vertices;
  desc.numFaces = t->num_faces;
  desc.numVertsPerFace = t->verts_per_face;
  desc.vertIndicesPerFace = t->face_vertices;
  desc.numCreases = t->num_creases;
  desc.creaseVertexIndexPairs = t->crease_vertex_pairs;
  desc.creaseWeights = t->crease_sharpness;
  desc.numCorners = t->num_corners;
  desc.cornerVertexIndices = t->corner_vertices;
  desc.cornerWeights = t->corner_sharpness;
  Far::TopologyDescriptor::FVarChannel channel;
  if (t->num_fvar_values > 0) {
    channel.numValues = t->num_fvar_values;
    channel.valueIndices = t->fvar_indices;
    desc.numFVarChannels = 1;
    desc.fvarChannels = &channel;
  }
  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(
      static_cast<Sdc::Options::VtxBoundaryInterpolation>(t->vtx_boundary_interpolation));
  sdc.SetFVarLinearInterpolation(
      static_cast<Sdc::Options::FVarLinearInterpolation>(t->fvar_linear_interpolation));
  sdc.SetCreasingMethod(static_cast<Sdc::Options::CreasingMethod>(t->creasing_method));
  sdc.SetTriangleSubdivision(
      static_cast<Sdc::Options::TriangleSubdivision>(t->triangle_subdivision));
  Far::TopologyRefiner* refiner =
      RefinerFactory::Create(desc, RefinerFactory::Options(Sdc::SCHEME_CATMARK, sdc));
  if (!refiner) {
    why = "TopologyRefinerFactory refused the mesh: " +
          (last_osd_error.empty() ? std::string("no reason given") : last_osd_error);
  }
  return std::unique_ptr<Far::TopologyRefiner>(refiner);
}

// A point of a primvar buffer for PrimvarRefiner: N doubles.
template <int N>
struct Point {
  double x[N];
  void Clear() {
    for (int i = 0; i < N; ++i) x[i] = 0.0;
  }
  void AddWithWeight(const Point& p, double w) {
    for (int i = 0; i < N; ++i) x[i] += w * p.x[i];
  }
};

}  // namespace

// ---- Uniform refinement --------------------------------------------------------------------

struct surfkit_osd_uniform {
  std::unique_ptr<Far::TopologyRefiner> refiner;
  int levels = 0;
  bool fvar = false;
};

extern "C" int surfkit_osd_uniform_create(const surfkit_osd_topology* topology, int levels,
                                          surfkit_osd_uniform** out,
                                          surfkit_osd_uniform_counts* counts, char** error) {
  return guarded(error, [&]() -> std::string {
    if (!out || !counts) return "null output pointer";
    *out = nullptr;
    if (levels < 1 || levels > 10) return "levels must be 1..=10";
    auto result = std::make_unique<surfkit_osd_uniform>();
    std::string why;
    result->refiner = make_refiner(topology, why);
    if (!result->refiner) return why;
    result->levels = levels;
    result->fvar = topology->num_fvar_values > 0;
    result->refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
    const Far::TopologyLevel& last = result->refiner->GetLevel(levels);
    counts->num_vertices = last.GetNumVertices();
    counts->num_faces = last.GetNumFaces();
    counts->num_fvar_values = result->fvar ? last.GetNumFVarValues(0) : 0;
    *out = result.release();
    return "";
  });
}

namespace {

// Interpolates `src` (level 0) through every level; the last level goes straight into
// `out`, intermediate levels into two scratch buffers.
template <int N, class Apply>
void interpolate_levels(int levels, const Point<N>* src, Point<N>* out,
                        const Far::TopologyRefiner& refiner, Apply&& apply) {
  std::vector<Point<N>> a, b;
  const Point<N>* from = src;
  for (int level = 1; level <= levels; ++level) {
    if (level == levels) {
      apply(level, from, out);
    } else {
      std::vector<Point<N>>& to = (level % 2) ? a : b;
      to.resize(refiner.GetLevel(level).GetNumVertices());
      apply(level, from, to.data());
      from = to.data();
    }
  }
}

}  // namespace

extern "C" int surfkit_osd_uniform_copy(const surfkit_osd_uniform* r, const double* positions,
                                        const double* fvar_values, double* out_positions,
                                        int* out_face_vertices, double* out_fvar_values,
                                        int* out_fvar_indices, char** error) {
  return guarded(error, [&]() -> std::string {
    if (!r || !positions || !out_positions || !out_face_vertices) return "null pointer";
    if (r->fvar && (!fvar_values || !out_fvar_values || !out_fvar_indices))
      return "null face-varying pointer";
    const Far::TopologyRefiner& refiner = *r->refiner;
    Far::PrimvarRefinerReal<double> primvar(refiner);
    interpolate_levels<3>(r->levels, reinterpret_cast<const Point<3>*>(positions),
                          reinterpret_cast<Point<3>*>(out_positions), refiner,
                          [&](int level, const Point<3>* from, Point<3>* to) {
                            primvar.Interpolate(level, from, to);
                          });
    if (r->fvar) {
      // Face-varying buffers are sized by the values of each level, not the vertices.
      std::vector<Point<2>> a, b;
      const Point<2>* from = reinterpret_cast<const Point<2>*>(fvar_values);
      for (int level = 1; level <= r->levels; ++level) {
        Point<2>* to;
        if (level == r->levels) {
          to = reinterpret_cast<Point<2>*>(out_fvar_values);
        } else {
          std::vector<Point<2>>& buf = (level % 2) ? a : b;
          buf.resize(refiner.GetLevel(level).GetNumFVarValues(0));
          to = buf.data();
        }
        primvar.InterpolateFaceVarying(level, from, to, 0);
        from = to;
      }
    }
    const Far::TopologyLevel& last = refiner.GetLevel(r->levels);
    const int nf = last.GetNumFaces();
    for (int f = 0; f < nf; ++f) {
      Far::ConstIndexArray fv = last.GetFaceVertices(f);
      if (fv.size() != 4) return "refined face is not a quad";
      std::copy(fv.begin(), fv.end(), out_face_vertices + 4 * f);
      if (r->fvar) {
        Far::ConstIndexArray fvv = last.GetFaceFVarValues(f, 0);
        std::copy(fvv.begin(), fvv.end(), out_fvar_indices + 4 * f);
      }
    }
    return "";
  });
}

extern "C" void surfkit_osd_uniform_destroy(surfkit_osd_uniform* r) { delete r; }

// ---- Adaptive patch table -------------------------------------------------------------------

struct surfkit_osd_patches {
  std::unique_ptr<Far::TopologyRefiner> refiner;
  std::unique_ptr<const Far::PatchTable> table;
  std::unique_ptr<surfkit_osd::StencilComposer> stencils;  // points >= control verts
  std::vector<Far::PatchTable::PatchHandle> handles;       // per patch
  int num_control_vertices = 0;
  int num_patch_points = 0;
};

namespace {

Far::PatchTableFactory::Options patch_options(int isolation) {
  Far::PatchTableFactory::Options popt(isolation);
  popt.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_BSPLINE_BASIS);
  popt.SetPatchPrecision<double>();
  popt.generateVaryingTables = false;
  popt.generateVaryingLocalPoints = false;
  return popt;
}

// An estimate (an upper bound on the meshes measured) of the stencil weights of the B-spline
// end caps Far::PatchTableFactory adds after refiner's last level: for each face of that
// level with an extraordinary corner, 16 local points on at most the face's one-ring, which
// is 16 points around a regular quad and 2 more per edge beyond 4 at each corner (an n-gon:
// 2n + 1 per corner). A triangle grid measured 86 M weights against 87 M estimated at
// level 1, 44 M against 193 M at level 2 (one extraordinary corner: points shared).
size_t end_cap_weight_bound(const Far::TopologyRefiner& refiner) {
  const Far::TopologyLevel& last = refiner.GetLevel(refiner.GetMaxLevel());
  size_t total = 0;
  for (int f = 0; f < last.GetNumFaces(); ++f) {
    Far::ConstIndexArray corners = last.GetFaceVertices(f);
    bool irregular = false;
    size_t ring = corners.size() == 4 ? 16 : 0;
    for (int k = 0; k < corners.size(); ++k) {
      const size_t n = static_cast<size_t>(last.GetVertexFaces(corners[k]).size());
      ring += corners.size() == 4 ? 2 * (n > 4 ? n - 4 : 0) : 2 * n + 1;
      irregular = irregular || !last.IsVertexValenceRegular(corners[k]);
    }
    if (irregular || corners.size() != 4) total += 16 * ring;
  }
  return total;
}

// Refines adaptively to the highest level <= max_isolation whose refined vertices (all
// levels) stay within max_points and whose end caps' estimated stencil weights within
// max_weights, never refining a level that would pass the points: level by level unless
// even 4^max_isolation times the control mesh fits. Returns the level, 0 when even level 1
// does not fit.
int refine_within(Far::TopologyRefiner& refiner, int max_isolation, size_t max_points,
                  size_t max_weights) {
  const Far::TopologyLevel& base = refiner.GetLevel(0);
  const double bound = (static_cast<double>(base.GetNumVertices()) + base.GetNumFaces()) *
                       std::ldexp(1.0, 2 * max_isolation);
  if (bound <= static_cast<double>(max_points)) {
    refiner.RefineAdaptive(patch_options(max_isolation).GetRefineAdaptiveOptions());
    if (end_cap_weight_bound(refiner) <= max_weights) return max_isolation;
    refiner.Unrefine();
  }
  for (int level = 1; level <= max_isolation; ++level) {
    if (level > 1) refiner.Unrefine();
    refiner.RefineAdaptive(patch_options(level).GetRefineAdaptiveOptions());
    const size_t total = static_cast<size_t>(refiner.GetNumVerticesTotal());
    if (total > max_points || end_cap_weight_bound(refiner) > max_weights) {
      refiner.Unrefine();
      if (level == 1) return 0;
      refiner.RefineAdaptive(patch_options(level - 1).GetRefineAdaptiveOptions());
      return level - 1;
    }
    // A level has at most four times the vertices of the one before it (each refined face
    // splits into four): stop where the next one could pass the limit, or adds nothing.
    const int deepest = refiner.GetMaxLevel();
    const size_t last = static_cast<size_t>(refiner.GetLevel(deepest).GetNumVertices());
    if (deepest < level || total + 4 * last > max_points) return level;
  }
  return max_isolation;
}

}  // namespace

extern "C" int surfkit_osd_patches_create(const surfkit_osd_topology* topology,
                                          int max_isolation,
                                          const surfkit_osd_patch_limits* limits,
                                          surfkit_osd_patches** out,
                                          surfkit_osd_patch_counts* counts, char** error) {
  bool over_budget = false;
  const int status = guarded(error, [&]() -> std::string {
    if (!out || !counts || !limits) return "null pointer";
    *out = nullptr;
    if (max_isolation < 1 || max_isolation > 10) return "max_isolation must be 1..=10";
    auto result = std::make_unique<surfkit_osd_patches>();
    std::string why;
    result->refiner = make_refiner(topology, why);
    if (!result->refiner) return why;
    Far::TopologyRefiner& refiner = *result->refiner;

    // Far::PatchTableFactory allocates the end caps' local points itself: the level is
    // chosen so that their estimate fits too.
    const size_t budget = std::min(limits->max_stencil_weights, static_cast<size_t>(INT_MAX));
    const int isolation =
        refine_within(refiner, max_isolation, limits->max_refined_points, budget);
    if (isolation == 0) {
      over_budget = true;
      return "refining once adaptively makes more than " +
             std::to_string(limits->max_refined_points) + " vertices or end caps of more than " +
             std::to_string(budget) + " stencil weights";
    }
    const Far::PatchTableFactory::Options popt = patch_options(isolation);
    result->table.reset(Far::PatchTableFactory::Create(refiner, popt));
    if (!result->table) return "PatchTableFactory::Create failed: " + last_osd_error;
    const Far::PatchTable& table = *result->table;

    // Stencils of every refined vertex (all levels) in terms of the control vertices; the
    // local points' stencils stay in the table (copied out once by surfkit_osd_patches_copy).
    // int indices on the Rust side bound the total.
    const int ncv = refiner.GetLevel(0).GetNumVertices();
    result->stencils = std::make_unique<surfkit_osd::StencilComposer>(ncv, budget);
    surfkit_osd::StencilComposer& st = *result->stencils;
    why = st.add_refined_levels(refiner);
    if (!why.empty()) return why;
    const Far::StencilTableReal<double>* local = table.GetLocalPointStencilTable<double>();
    const size_t local_weights = local ? local->GetControlIndices().size() : 0;
    if (st.over_budget() || st.indices.size() + local_weights > budget) {
      over_budget = true;
      return "the limit surface at isolation level " + std::to_string(isolation) +
             " needs more than " + std::to_string(budget) + " stencil weights";
    }
    const size_t local_count = local ? static_cast<size_t>(local->GetNumStencils()) : 0;

    result->num_control_vertices = ncv;
    result->num_patch_points = refiner.GetNumVerticesTotal() + table.GetNumLocalPoints();
    if (static_cast<int>(st.stencil_count() + local_count) != result->num_patch_points - ncv)
      return "stencil count " + std::to_string(st.stencil_count() + local_count) +
             " does not match the patch points " + std::to_string(result->num_patch_points - ncv);

    for (int a = 0, global = 0; a < table.GetNumPatchArrays(); ++a) {
      Far::PatchDescriptor d = table.GetPatchArrayDescriptor(a);
      if (d.GetType() != Far::PatchDescriptor::REGULAR || d.GetNumControlVertices() != 16)
        return "patch array " + std::to_string(a) + " is not of regular B-spline patches";
      for (int p = 0; p < table.GetNumPatches(a); ++p, ++global) {
        Far::PatchTable::PatchHandle h;
        h.arrayIndex = a;
        h.patchIndex = global;
        h.vertIndex = p * 16;
        result->handles.push_back(h);
      }
    }
    counts->num_patches = static_cast<int>(result->handles.size());
    counts->num_ptex_faces = table.GetNumPtexFaces();
    counts->num_control_vertices = result->num_control_vertices;
    counts->num_patch_points = result->num_patch_points;
    counts->num_stencil_weights = static_cast<int>(st.indices.size() + local_weights);
    counts->isolation = isolation;
    *out = result.release();
    return "";
  });
  return over_budget ? 3 : status;
}

extern "C" int surfkit_osd_patches_copy(const surfkit_osd_patches* r,
                                        const surfkit_osd_patch_arrays* a, char** error) {
  return guarded(error, [&]() -> std::string {
    if (!r || !a) return "null pointer";
    const Far::PatchTable& table = *r->table;
    for (size_t i = 0; i < r->handles.size(); ++i) {
      const auto& h = r->handles[i];
      Far::ConstIndexArray cv = table.GetPatchVertices(h);
      for (int k = 0; k < 16; ++k) a->patch_points[16 * i + k] = cv[k];
      Far::PatchParam param = table.GetPatchParam(h);
      const double frac = param.GetParamFraction();
      a->ptex_face[i] = param.GetFaceId();
      a->depth[i] = param.GetDepth();
      a->boundary_mask[i] = param.GetBoundary();
      a->is_regular[i] = param.IsRegular() ? 1 : 0;
      a->u0[i] = param.GetU() * frac;
      a->v0[i] = param.GetV() * frac;
      a->size[i] = frac;
    }
    Far::PtexIndices ptex(*r->refiner);
    const int nf = r->refiner->GetLevel(0).GetNumFaces();
    for (int f = 0; f < nf; ++f) a->ptex_of_face[f] = ptex.GetFaceId(f);
    a->ptex_of_face[nf] = ptex.GetNumFaces();
    return "";
  });
}

extern "C" int surfkit_osd_patches_stencils(const surfkit_osd_patches* r,
                                            surfkit_osd_stencils* out, char** error) {
  return guarded(error, [&]() -> std::string {
    if (!r || !out) return "null pointer";
    const auto& st = *r->stencils;
    out->refined_count = st.stencil_count();
    out->refined_offsets = st.offsets.data();
    out->refined_indices = st.indices.data();
    out->refined_weights = st.weights.data();
    const Far::StencilTableReal<double>* local = r->table->GetLocalPointStencilTable<double>();
    const bool any = local && local->GetNumStencils() > 0;
    out->local_count = any ? static_cast<size_t>(local->GetNumStencils()) : 0;
    out->local_offsets = any ? local->GetOffsets().data() : nullptr;
    out->local_sizes = any ? local->GetSizes().data() : nullptr;
    out->local_entries = any ? local->GetControlIndices().size() : 0;
    out->local_indices = any ? local->GetControlIndices().data() : nullptr;
    out->local_weights = any ? local->GetWeights().data() : nullptr;
    if (any && local->GetWeights().size() != out->local_entries)
      return "local point stencils of unequal lengths";
    return "";
  });
}

extern "C" int surfkit_osd_patches_evaluate_basis(const surfkit_osd_patches* r, int n,
                                                  const int* patch, const double* u,
                                                  const double* v, double* weights,
                                                  char** error) {
  return guarded(error, [&]() -> std::string {
    if (!r || (n > 0 && (!patch || !u || !v || !weights))) return "null pointer";
    const int np = static_cast<int>(r->handles.size());
    for (int i = 0; i < n; ++i) {
      if (patch[i] < 0 || patch[i] >= np)
        return "patch index " + std::to_string(patch[i]) + " out of range";
      double* w = weights + 96 * i;
      r->table->EvaluateBasis(r->handles[patch[i]], u[i], v[i], w, w + 16, w + 32, w + 48,
                              w + 64, w + 80);
    }
    return "";
  });
}

extern "C" void surfkit_osd_patches_destroy(surfkit_osd_patches* r) { delete r; }
