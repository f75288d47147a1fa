// surfkit for OpenMesh programs: header-only C++17 templates over any OpenMesh mesh type
// (PolyMesh_ArrayKernelT / TriMesh_ArrayKernelT with float or double points), in the style
// of OpenMesh's own Tools (DecimaterT<Mesh>, SmootherT<Mesh>). They flatten the caller's
// mesh into surfkit's C ABI (include/surfkit.h), call it, and map ids back to OpenMesh
// handles; failures throw surfkit::Error. Deleted-but-not-collected elements are skipped
// (handles stay the caller's).
//
//   #include <surfkit/openmesh.hh>
//   surfkit::EatReport r = surfkit::eat(mesh);        // the Euler Accompanying Test
//   surfkit::FairReport q = surfkit::fair(mesh);      // optimized points written back
//   Mesh fine = surfkit::subdivide(mesh, 2);          // Catmull–Clark with OpenSubdiv
//
// Link: pkg-config --cflags --libs surfkit, or find_package(surfkit CONFIG REQUIRED) and
// target_link_libraries(app surfkit::surfkit).
#ifndef SURFKIT_OPENMESH_HH
#define SURFKIT_OPENMESH_HH

#include <surfkit.h>

#include <OpenMesh/Core/Mesh/Handles.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Core/Utils/Property.hh>

#include <algorithm>
#include <array>
#include <cstdint>
#include <exception>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace surfkit {

/// A failed surfkit call: the C side's status (SURFKIT_*) and its message.
class Error : public std::runtime_error {
 public:
  Error(int status, const std::string& message) : std::runtime_error(message), status_(status) {}
  /// SURFKIT_INVALID_INPUT, SURFKIT_IO, SURFKIT_PARSE, SURFKIT_TOPOLOGY, SURFKIT_SOLVER, …
  int status() const noexcept { return status_; }

 private:
  int status_;
};

namespace detail {

/// Throws surfkit::Error for a non-zero status, with the thread's last message.
inline void check(int status) {
  if (status != SURFKIT_OK) throw Error(status, surfkit_last_error());
}

struct MeshFree {
  void operator()(SurfkitMesh* m) const noexcept { surfkit_mesh_free(m); }
};
struct EatReportFree {
  void operator()(SurfkitEatReport* r) const noexcept { surfkit_eat_report_free(r); }
};
struct RegistryFree {
  void operator()(SurfkitRegistry* r) const noexcept { surfkit_registry_free(r); }
};
struct LimitFree {
  void operator()(SurfkitLimit* l) const noexcept { surfkit_limit_free(l); }
};
struct FairReportFree {
  void operator()(SurfkitFairReport* r) const noexcept { surfkit_fair_report_free(r); }
};
struct SplineFree {
  void operator()(SurfkitSpline* s) const noexcept { surfkit_spline_free(s); }
};

using MeshPtr = std::unique_ptr<SurfkitMesh, MeshFree>;

/// The caller's mesh as surfkit's flat arrays, with the maps between OpenMesh handles and
/// surfkit's compact ids (deleted elements skipped).
template <class Mesh>
struct Flattened {
  std::vector<double> positions;
  std::vector<uint32_t> offsets{0};
  std::vector<uint32_t> indices;
  std::vector<OpenMesh::VertexHandle> vertex_of;  // compact id -> handle
  std::vector<OpenMesh::FaceHandle> face_of;      // compact id -> handle
  std::vector<int64_t> compact_vertex;            // handle idx -> compact id or -1

  explicit Flattened(const Mesh& mesh) : compact_vertex(mesh.n_vertices(), -1) {
    positions.reserve(3 * mesh.n_vertices());
    vertex_of.reserve(mesh.n_vertices());
    for (auto vh : mesh.vertices()) {  // skips deleted vertices when status is present
      compact_vertex[vh.idx()] = static_cast<int64_t>(vertex_of.size());
      vertex_of.push_back(vh);
      const auto& p = mesh.point(vh);
      for (int k = 0; k < 3; ++k) positions.push_back(static_cast<double>(p[k]));
    }
    face_of.reserve(mesh.n_faces());
    offsets.reserve(mesh.n_faces() + 1);
    indices.reserve(mesh.n_halfedges());  // every corner is a face's half-edge
    for (auto fh : mesh.faces()) {
      face_of.push_back(fh);
      // The face's loop as fv_range walks it (to-vertex of halfedge_handle(fh) first), by
      // next_halfedge_handle directly: the circulator's checks cost a third of the copy.
      const auto first = mesh.halfedge_handle(fh);
      auto h = first;
      do {
        indices.push_back(static_cast<uint32_t>(compact_vertex[mesh.to_vertex_handle(h).idx()]));
        h = mesh.next_halfedge_handle(h);
      } while (h != first);
      offsets.push_back(static_cast<uint32_t>(indices.size()));
    }
  }

  MeshPtr make() const {
    SurfkitMesh* out = nullptr;
    check(surfkit_mesh_new(positions.data(), vertex_of.size(), offsets.data(), face_of.size(),
                           indices.data(), indices.size(), &out));
    return MeshPtr(out);
  }
};

/// A new mesh of the caller's type from a surfkit mesh.
template <class Mesh>
Mesh to_openmesh(const SurfkitMesh* source) {
  size_t nv = 0, nf = 0, ni = 0;
  check(surfkit_mesh_counts(source, &nv, &nf, &ni));
  const double* positions = nullptr;
  const uint32_t* offsets = nullptr;
  const uint32_t* indices = nullptr;
  check(surfkit_mesh_arrays(source, &positions, &offsets, &indices));
  Mesh mesh;
  mesh.reserve(nv, 2 * ni, nf);
  using Scalar = typename Mesh::Point::value_type;
  std::vector<typename Mesh::VertexHandle> handles(nv);
  for (size_t v = 0; v < nv; ++v)
    handles[v] = mesh.add_vertex(typename Mesh::Point(static_cast<Scalar>(positions[3 * v]),
                                                      static_cast<Scalar>(positions[3 * v + 1]),
                                                      static_cast<Scalar>(positions[3 * v + 2])));
  std::vector<typename Mesh::VertexHandle> corners;
  for (size_t f = 0; f < nf; ++f) {
    corners.clear();
    for (uint32_t k = offsets[f]; k < offsets[f + 1]; ++k) corners.push_back(handles[indices[k]]);
    if (!mesh.add_face(corners).is_valid())
      throw Error(SURFKIT_TOPOLOGY, "surfkit: OpenMesh refused face " + std::to_string(f) +
                                        " of the result (a complex edge or vertex)");
  }
  return mesh;
}

}  // namespace detail

// ---------------------------------------------------------------------------------------
// The Euler Accompanying Test

/// Options of eat(): the defaults of `surfkit eat`.
struct EatOptions {
  /// Build OpenMesh's half-edge structure inside surfkit too (refusal reports, loop walks).
  bool halfedge = true;
  /// Distance under which distinct vertices count as coincident (0: same coordinates).
  double weld_tolerance = 0.0;
  /// A boundary vertex within this fraction of a boundary edge's length of that edge is a
  /// T-vertex on it (a crack).
  double crack_tolerance = 0.01;
  /// Test points (facet count, expected χ); one entry with facets = 0 means the whole mesh.
  std::vector<std::pair<size_t, int64_t>> test_points;
  /// Check every suggested fix by applying it to a copy and scanning that (Flaw::fix_verified).
  bool check_fixes = true;
};

/// One topological flaw, located with the caller's handles.
struct Flaw {
  std::string kind;  // the CLI's kind names: "non_manifold_edge", "hole", "crack", …
  std::vector<OpenMesh::VertexHandle> vertices;
  std::vector<OpenMesh::FaceHandle> faces;
  /// The flaw's edges that exist in the mesh (e.g. the non-manifold edge, a hole's rim).
  std::vector<OpenMesh::EdgeHandle> edges;
  std::array<double, 3> position{};
  long component = -1;
  std::string description;
  std::string suggested_fix;
  /// Whether applying suggested_fix to a copy removed the flaw; empty when not checked.
  std::optional<bool> fix_verified;
};

/// A test point's outcome.
struct TestPoint {
  size_t facets = 0;
  int64_t expected_euler_characteristic = 0;
  int64_t euler_characteristic = 0;
  bool verified = false;
};

/// What eat() found; counts as `surfkit eat --json` gives them under report.counts (its
/// nulls as −1), with `vertices` its vertices_referenced and `faces` its facets.
struct EatReport {
  /// Every vertex of the mesh, and those a face uses.
  size_t vertices_in_file = 0, vertices = 0;
  size_t edges = 0, faces = 0;
  int64_t euler_characteristic = 0;
  size_t boundary_edges = 0, boundary_loops = 0, components = 0;
  size_t non_manifold_edges = 0, non_manifold_vertices = 0, unreferenced_vertices = 0;
  size_t duplicated_facets = 0, degenerate_facets = 0, coincident_vertices = 0;
  /// Edges whose two facets traverse them in the same direction.
  size_t inconsistent_orientation_edges = 0;
  /// Genus of a closed orientable manifold, else −1.
  int64_t genus = -1;
  /// Cross-caps when every component is a non-orientable manifold (Möbius strip 1), else −1.
  int64_t non_orientable_genus = -1;
  /// Boundary loops walked half-edge by half-edge within each fan (differs from
  /// boundary_loops at pinch vertices); −1 where a non-manifold edge or an inconsistent
  /// orientation leaves it undefined.
  int64_t boundary_loops_walk = -1;
  /// Faces surfkit's own OpenMesh structure refused (report.halfedge.refused in the JSON;
  /// 0 with EatOptions::halfedge off).
  size_t refused_faces = 0;
  bool verified = true;
  std::vector<TestPoint> test_points;
  std::vector<Flaw> flaws;
  /// The whole report as JSON (the object `surfkit eat --json` prints under "report").
  std::string json;
};

namespace detail {

inline EatReport read_eat_report(SurfkitEatReport* raw) {
  SurfkitEatCounts c{};
  check(surfkit_eat_report_counts(raw, &c));
  EatReport r;
  r.vertices_in_file = c.vertices_in_file;
  r.vertices = c.vertices;
  r.edges = c.edges;
  r.faces = c.faces;
  r.euler_characteristic = c.euler_characteristic;
  r.boundary_edges = c.boundary_edges;
  r.boundary_loops = c.boundary_loops;
  r.components = c.components;
  r.non_manifold_edges = c.non_manifold_edges;
  r.non_manifold_vertices = c.non_manifold_vertices;
  r.unreferenced_vertices = c.unreferenced_vertices;
  r.duplicated_facets = c.duplicated_facets;
  r.degenerate_facets = c.degenerate_facets;
  r.coincident_vertices = c.coincident_vertices;
  r.inconsistent_orientation_edges = c.inconsistent_orientation_edges;
  r.genus = c.genus;
  r.non_orientable_genus = c.non_orientable_genus;
  r.boundary_loops_walk = c.boundary_loops_walk;
  r.refused_faces = c.refused_faces;
  r.verified = c.verified != 0;
  size_t points = 0;
  check(surfkit_eat_report_test_point(raw, 0, &points, nullptr));
  for (size_t i = 0; i < points; ++i) {
    SurfkitTestPoint t{};
    check(surfkit_eat_report_test_point(raw, i, nullptr, &t));
    r.test_points.push_back({t.facets, t.expected_euler_characteristic, t.euler_characteristic, t.verified != 0});
  }
  const char* json = nullptr;
  check(surfkit_eat_report_json(raw, &json));
  r.json = json;
  return r;
}

}  // namespace detail

/// The Euler Accompanying Test (Liu et al. 2020) on the caller's mesh: V, E, F, χ, test
/// points, and every topological flaw with OpenMesh handles.
template <class Mesh>
EatReport eat(const Mesh& mesh, const EatOptions& options = EatOptions{}) {
  detail::Flattened<Mesh> flat(mesh);
  auto soup = flat.make();
  SurfkitEatOptions o{};
  detail::check(surfkit_eat_options_default(&o));
  o.halfedge = options.halfedge ? 1 : 0;
  o.weld_tolerance = options.weld_tolerance;
  o.crack_tolerance = options.crack_tolerance;
  o.check_fixes = options.check_fixes ? 1 : 0;
  std::vector<size_t> facets;
  std::vector<int64_t> expected;
  for (const auto& [f, chi] : options.test_points) {
    if (f != 0) facets.push_back(f);
    expected.push_back(chi);
  }
  if (!facets.empty() && facets.size() != expected.size())
    throw Error(SURFKIT_INVALID_INPUT, "surfkit::eat: a whole-mesh test point (facets = 0) "
                                       "cannot be mixed with facet-count test points");
  if (facets.empty() && expected.size() > 1)
    throw Error(SURFKIT_INVALID_INPUT, "surfkit::eat: " + std::to_string(expected.size()) +
                                           " whole-mesh test points (facets = 0): give one");
  // No facet counts: a null pointer, which the C door reads as the whole mesh.
  o.test_point_facets = facets.empty() ? nullptr : facets.data();
  o.test_point_expected = expected.data();
  o.test_point_count = facets.empty() ? expected.size() : facets.size();
  SurfkitEatReport* raw_ptr = nullptr;
  detail::check(surfkit_eat_scan(soup.get(), &o, &raw_ptr));
  std::unique_ptr<SurfkitEatReport, detail::EatReportFree> raw(raw_ptr);
  EatReport r = detail::read_eat_report(raw.get());
  size_t count = 0;
  detail::check(surfkit_eat_report_flaw_count(raw.get(), &count));
  r.flaws.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    SurfkitFlaw f{};
    detail::check(surfkit_eat_report_flaw(raw.get(), i, &f));
    Flaw flaw;
    flaw.kind = f.kind;
    for (size_t k = 0; k < f.vertex_count; ++k) flaw.vertices.push_back(flat.vertex_of.at(f.vertices[k]));
    for (size_t k = 0; k < f.face_count; ++k) flaw.faces.push_back(flat.face_of.at(f.faces[k]));
    // The flaw's edges: between consecutive listed vertices (a loop closes), where the
    // mesh has that edge.
    const size_t n = flaw.vertices.size();
    for (size_t k = 0; n >= 2 && k < (n == 2 ? 1 : n); ++k) {
      auto he = mesh.find_halfedge(flaw.vertices[k], flaw.vertices[(k + 1) % n]);
      if (!he.is_valid()) he = mesh.find_halfedge(flaw.vertices[(k + 1) % n], flaw.vertices[k]);
      if (he.is_valid()) flaw.edges.push_back(mesh.edge_handle(he));
    }
    flaw.position = {f.position[0], f.position[1], f.position[2]};
    flaw.component = static_cast<long>(f.component);
    flaw.description = f.description;
    flaw.suggested_fix = f.suggested_fix;
    if (f.fix_verified >= 0) flaw.fix_verified = f.fix_verified == 1;
    r.flaws.push_back(std::move(flaw));
  }
  return r;
}

/// The accompanying test while a program builds `mesh` facet by facet (paper §3–4):
/// add_face() mirrors mesh.add_face and registers the facet even when OpenMesh refuses
/// it (the refusal is kept, not lost); checkpoint(expected χ) is a test point.
template <class Mesh>
class EatCompanion {
 public:
  /// A refused facet: its registry id, corners, and what OpenMesh said (its omerr
  /// message, captured instead of printed) or, for a facet not given to OpenMesh,
  /// "degenerate: " and why.
  struct Refusal {
    uint32_t facet;
    std::vector<OpenMesh::VertexHandle> corners;
    std::string message;
  };
  /// A test point's outcome; `suspects` are the facets added since the last verified
  /// point (registry ids, with the face handle where OpenMesh took the facet).
  struct Checkpoint {
    bool verified = false;
    int64_t expected_euler_characteristic = 0;
    size_t vertices = 0, edges = 0, facets = 0;
    int64_t euler_characteristic = 0;
    size_t last_verified_facets = 0;
    std::vector<std::pair<uint32_t, OpenMesh::FaceHandle>> suspects;
  };

  explicit EatCompanion(Mesh& mesh) : mesh_(mesh) {
    SurfkitRegistry* r = nullptr;
    detail::check(surfkit_registry_new(static_cast<uint32_t>(mesh.n_vertices()), &r));
    registry_.reset(r);
  }

  /// Registers the facet, then adds it to the mesh; returns the new face handle, invalid
  /// when OpenMesh refused the facet (see refusals()). A degenerate facet (fewer than 3
  /// corners or a repeated vertex) is registered (the EAT counts it) but never given to
  /// OpenMesh, whose add_face asserts on it: it is refused with the reason "degenerate".
  typename Mesh::FaceHandle add_face(const std::vector<typename Mesh::VertexHandle>& corners) {
    std::vector<uint32_t> ids;
    ids.reserve(corners.size());
    for (auto vh : corners) {
      if (!vh.is_valid() || static_cast<size_t>(vh.idx()) >= mesh_.n_vertices())
        throw Error(SURFKIT_INVALID_INPUT, "surfkit::EatCompanion::add_face: vertex handle " +
                                               std::to_string(vh.idx()) + " is not a vertex of the mesh");
      ids.push_back(static_cast<uint32_t>(vh.idx()));
    }
    detail::check(surfkit_registry_set_vertex_count(registry_.get(), static_cast<uint32_t>(mesh_.n_vertices())));
    uint32_t facet = 0;
    detail::check(surfkit_registry_add_facet(registry_.get(), ids.data(), ids.size(), next_, &facet));
    ++next_;
    if (const char* why = degenerate(ids)) {
      face_of_.push_back(typename Mesh::FaceHandle());
      refusals_.push_back({facet, {corners.begin(), corners.end()}, std::string("degenerate: ") + why});
      return typename Mesh::FaceHandle();
    }
    // OpenMesh says why it refuses on omerr, which writes to std::cerr: captured by
    // swapping std::cerr's buffer for the call (mostream's connect/disconnect would leak
    // a target per call). Not for programs writing to std::cerr from another thread now.
    std::ostringstream said;
    ::omerr().flush();
    std::streambuf* cerr_buffer = std::cerr.rdbuf(said.rdbuf());
    auto fh = mesh_.add_face(corners);
    ::omerr().flush();
    std::cerr.rdbuf(cerr_buffer);
    face_of_.push_back(fh);
    if (!fh.is_valid()) {
      std::string message = said.str();
      while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
      refusals_.push_back({facet, {corners.begin(), corners.end()}, message});
    }
    return fh;
  }

  /// A test point: is χ of the facets registered so far `expected`?
  Checkpoint checkpoint(int64_t expected) {
    SurfkitCheckpoint c{};
    detail::check(surfkit_registry_checkpoint(registry_.get(), expected, &c));
    Checkpoint out;
    out.verified = c.verified != 0;
    out.expected_euler_characteristic = c.expected_euler_characteristic;
    out.vertices = c.statistics.vertices;
    out.edges = c.statistics.edges;
    out.facets = c.statistics.facets;
    out.euler_characteristic = c.statistics.euler_characteristic;
    out.last_verified_facets = c.last_verified_facets;
    const uint32_t* ids = nullptr;
    size_t n = 0;
    detail::check(surfkit_registry_suspects(registry_.get(), &ids, &n));
    for (size_t i = 0; i < n; ++i) out.suspects.emplace_back(ids[i], face_of_.at(ids[i]));
    return out;
  }

  /// Facets OpenMesh refused (complex edge or vertex) or that were not given to it
  /// (degenerate), in registration order.
  const std::vector<Refusal>& refusals() const noexcept { return refusals_; }

 private:
  /// Why a facet is degenerate (fewer than 3 corners, a repeated vertex), or null.
  static const char* degenerate(const std::vector<uint32_t>& ids) {
    if (ids.size() < 3) return "fewer than 3 corners";
    std::vector<uint32_t> sorted(ids);
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return "a repeated vertex";
    return nullptr;
  }

  Mesh& mesh_;
  std::unique_ptr<SurfkitRegistry, detail::RegistryFree> registry_;
  std::vector<typename Mesh::FaceHandle> face_of_;
  std::vector<Refusal> refusals_;
  uint32_t next_ = 0;
};

// ---------------------------------------------------------------------------------------
// Subdivision

/// Options of subdivide() and LimitSurface.
struct SubdivOptions {
  int boundary = SURFKIT_BOUNDARY_EDGES_AND_CORNERS;
  int creasing = SURFKIT_CREASING_UNIFORM;
  /// Name of a float edge property holding crease sharpness (0 smooth, ≥ 10 infinitely
  /// sharp), read when the mesh has it.
  std::string crease_property = "crease_sharpness";
  /// Name of a float vertex property holding corner sharpness, read when present.
  std::string corner_property = "corner_sharpness";
};

namespace detail {

/// Creases and corners from the mesh's named properties, in compact ids.
template <class Mesh>
struct Features {
  std::vector<uint32_t> crease_vertices, corner_vertices;
  std::vector<float> crease_sharpness, corner_sharpness;
  SurfkitSubdivOptions options{};

  Features(const Mesh& mesh, const Flattened<Mesh>& flat, const SubdivOptions& o) {
    check(surfkit_subdiv_options_default(&options));
    options.boundary = o.boundary;
    options.creasing = o.creasing;
    OpenMesh::EPropHandleT<float> crease;
    if (!o.crease_property.empty() && mesh.get_property_handle(crease, o.crease_property)) {
      for (auto eh : mesh.edges()) {
        float s = mesh.property(crease, eh);
        if (s == 0.0f) continue;
        auto he = mesh.halfedge_handle(eh, 0);
        crease_vertices.push_back(static_cast<uint32_t>(flat.compact_vertex[mesh.from_vertex_handle(he).idx()]));
        crease_vertices.push_back(static_cast<uint32_t>(flat.compact_vertex[mesh.to_vertex_handle(he).idx()]));
        crease_sharpness.push_back(s);
      }
    }
    OpenMesh::VPropHandleT<float> corner;
    if (!o.corner_property.empty() && mesh.get_property_handle(corner, o.corner_property)) {
      for (auto vh : mesh.vertices()) {
        float s = mesh.property(corner, vh);
        if (s == 0.0f) continue;
        corner_vertices.push_back(static_cast<uint32_t>(flat.compact_vertex[vh.idx()]));
        corner_sharpness.push_back(s);
      }
    }
    options.crease_vertices = crease_vertices.data();
    options.crease_sharpness = crease_sharpness.data();
    options.crease_count = crease_sharpness.size();
    options.corner_vertices = corner_vertices.data();
    options.corner_sharpness = corner_sharpness.data();
    options.corner_count = corner_sharpness.size();
  }
};

}  // namespace detail

/// `levels` uniform Catmull–Clark refinements with OpenSubdiv, as a new mesh of the same
/// type (quads; the control vertices come first, in the caller's order minus deleted ones).
template <class Mesh>
Mesh subdivide(const Mesh& mesh, int levels, const SubdivOptions& options = SubdivOptions{}) {
  if (levels < 0) throw Error(SURFKIT_INVALID_INPUT, "surfkit::subdivide: levels must be ≥ 0");
  detail::Flattened<Mesh> flat(mesh);
  auto soup = flat.make();
  detail::Features<Mesh> features(mesh, flat, options);
  SurfkitMesh* out = nullptr;
  detail::check(surfkit_subdivide(soup.get(), static_cast<uint32_t>(levels), &features.options, &out));
  detail::MeshPtr fine(out);
  return detail::to_openmesh<Mesh>(fine.get());
}

/// A point of the limit surface with its derivatives (with respect to the face's (u, v))
/// and curvature.
struct LimitPoint {
  std::array<double, 3> position{}, du{}, dv{}, duu{}, duv{}, dvv{}, duuu{}, duuv{}, duvv{}, dvvv{};
  std::array<double, 3> normal{};
  double mean_curvature = 0, gaussian_curvature = 0, k1 = 0, k2 = 0;
};

/// The Catmull–Clark limit surface of a mesh (OpenSubdiv's bicubic patches, end caps after
/// `max_isolation` levels), evaluated at (face, u, v). For an n-gon, `corner` picks the
/// sub-face (ptex face) at that corner.
class LimitSurface {
 public:
  template <class Mesh>
  explicit LimitSurface(const Mesh& mesh, const SubdivOptions& options = SubdivOptions{}, int max_isolation = 4) {
    detail::Flattened<Mesh> flat(mesh);
    auto soup = flat.make();
    detail::Features<Mesh> features(mesh, flat, options);
    compact_face_.assign(mesh.n_faces(), -1);
    for (size_t f = 0; f < flat.face_of.size(); ++f) compact_face_[flat.face_of[f].idx()] = static_cast<int64_t>(f);
    SurfkitLimit* out = nullptr;
    detail::check(surfkit_limit_new(soup.get(), &features.options, static_cast<uint32_t>(max_isolation), &out));
    limit_.reset(out);
  }

  LimitPoint evaluate(OpenMesh::FaceHandle face, double u, double v, unsigned corner = 0) const {
    if (!face.is_valid() || static_cast<size_t>(face.idx()) >= compact_face_.size() || compact_face_[face.idx()] < 0)
      throw Error(SURFKIT_INVALID_INPUT, "surfkit::LimitSurface: face " + std::to_string(face.idx()) +
                                             " is not a face of the mesh");
    uint32_t first = 0, count = 0;
    detail::check(surfkit_limit_ptex_faces(limit_.get(), static_cast<uint32_t>(compact_face_[face.idx()]), &first, &count));
    if (corner >= count)
      throw Error(SURFKIT_INVALID_INPUT, "surfkit::LimitSurface: face " + std::to_string(face.idx()) + " has " +
                                             std::to_string(count) + " sub-faces, not corner " + std::to_string(corner));
    uint32_t ptex = first + corner;
    double d[30];
    detail::check(surfkit_limit_evaluate(limit_.get(), 1, &ptex, &u, &v, d));
    LimitPoint p;
    std::array<double, 3>* slots[10] = {&p.position, &p.du, &p.dv, &p.duu, &p.duv, &p.dvv, &p.duuu, &p.duuv, &p.duvv, &p.dvvv};
    for (int s = 0; s < 10; ++s) *slots[s] = {d[3 * s], d[3 * s + 1], d[3 * s + 2]};
    detail::check(surfkit_limit_curvature(limit_.get(), 1, &ptex, &u, &v, p.normal.data(), &p.mean_curvature,
                                          &p.gaussian_curvature, &p.k1, &p.k2));
    return p;
  }

 private:
  std::unique_ptr<SurfkitLimit, detail::LimitFree> limit_;
  std::vector<int64_t> compact_face_;
};

/// One point of the limit surface of `mesh` (builds the surface each call; keep a
/// LimitSurface to evaluate many points).
template <class Mesh>
LimitPoint limit(const Mesh& mesh, OpenMesh::FaceHandle face, double u, double v,
                 const SubdivOptions& options = SubdivOptions{}) {
  return LimitSurface(mesh, options).evaluate(face, u, v);
}

// ---------------------------------------------------------------------------------------
// Fairing (Kiciak's shape optimization)

/// One optimizer iteration, for progress display.
struct FairIteration {
  size_t iteration = 0;
  double f = 0, s = 0, q = 0, gradient_norm = 0, initial_gradient_norm = 0;
  bool levenberg_marquardt = false;
};

/// Options of fair(): the defaults of `surfkit fair`, except that the mesh is never
/// refined (the result is written back into the caller's mesh, topology untouched).
struct FairOptions {
  unsigned boundary_rings = 3;
  /// The surface: SURFKIT_SURFACE_G2 (Kiciak's curvature-continuous one, the default) or
  /// SURFKIT_SURFACE_CATMULL_CLARK (then c_special 0 means `surfkit fair`'s 0.01 for it).
  int surface = SURFKIT_SURFACE_G2;
  // 0: surfkit's default (that of `surfkit fair`) for each of these.
  double relative_gradient = 0;
  unsigned max_iterations = 0;
  unsigned isolation = 0;
  unsigned nodes = 0;
  double c_special = 0;
  /// C in F = S + C·c·Q (1: the paper's text; the author's program: 0.01).
  double regularization = 0;
  /// SURFKIT_METHOD_AUTO (by size, the default), SURFKIT_METHOD_PLAIN or
  /// SURFKIT_METHOD_MULTILEVEL (`surfkit fair --method`).
  int method = SURFKIT_METHOD_AUTO;
  /// The multilevel method starts from the optimum of the mesh this one un-subdivides to,
  /// refined (`surfkit fair --coarse-start`): faster on the junctions measured, but it may
  /// end in another local minimum. Not used when vertices are fixed (below).
  bool coarse_start = false;
  /// More fixed vertices; also fixed: locked vertices (mesh.status(vh).locked()) and those
  /// whose bool vertex property named `fixed_property` is true.
  std::vector<OpenMesh::VertexHandle> fixed;
  std::string fixed_property = "fixed";
  /// Called after every iteration; return false to stop (the points reached are written).
  std::function<bool(const FairIteration&)> progress;
};

/// What fair() did.
struct FairReport {
  bool converged = false, cancelled = false;
  size_t iterations = 0, hessian_evaluations = 0, free_vertices = 0;
  double s_before = 0, s_after = 0, f_before = 0, f_after = 0, q_before = 0, q_after = 0;
  double gradient_norm_before = 0, gradient_norm_after = 0;
  /// Stopped above the tolerance at the gradient's floor for double coordinates,
  /// coordinate_floor (|H u| for u their rounding): as close as doubles come.
  bool stalled = false;
  double coordinate_floor = 0;
  /// The surface optimized (SURFKIT_SURFACE_G2 or SURFKIT_SURFACE_CATMULL_CLARK).
  int surface = SURFKIT_SURFACE_G2;
  /// The method that ran (SURFKIT_METHOD_PLAIN or SURFKIT_METHOD_MULTILEVEL).
  int method = SURFKIT_METHOD_PLAIN;
  /// Whether the coarse stage ran (FairOptions::coarse_start) and the fine iteration started
  /// from its optimum (not when F there was above the mesh's own).
  bool coarse_stage = false, coarse_start_used = false;
  std::string json;
};

namespace detail {

/// Recomputes the normals `mesh` has after its points moved, as update_normals() does;
/// vertex and halfedge normals are made from face normals, so without those they are
/// computed through face normals requested for the call.
template <class Mesh>
void update_normals(Mesh& mesh) {
  if (mesh.has_face_normals()) {
    mesh.update_normals();
  } else if (mesh.has_vertex_normals() || mesh.has_halfedge_normals()) {
    mesh.request_face_normals();
    mesh.update_normals();
    mesh.release_face_normals();
  }
}

struct ProgressBridge {
  const std::function<bool(const FairIteration&)>* progress;
  std::exception_ptr error;

  static int call(const SurfkitFairIteration* it, void* self) noexcept {
    auto* b = static_cast<ProgressBridge*>(self);
    try {
      FairIteration i{it->iteration, it->f, it->s, it->q, it->gradient_norm, it->initial_gradient_norm,
                      it->levenberg_marquardt != 0};
      return (*b->progress)(i) ? 0 : 1;
    } catch (...) {  // never unwind through Rust frames: rethrown after the call
      b->error = std::current_exception();
      return 1;
    }
  }
};

}  // namespace detail

/// Optimizes the shape of the mesh's Catmull–Clark surface (Kiciak) and writes the
/// optimized points back with set_point; topology and handles are untouched, fixed
/// vertices keep their points bit for bit. The normals the mesh has (face, vertex,
/// halfedge) are then recomputed from the new points, as mesh.update_normals() computes
/// them. The mesh must meet the method's conditions (quads, special vertices apart), since
/// it is not refined here.
template <class Mesh>
FairReport fair(Mesh& mesh, const FairOptions& options = FairOptions{}) {
  detail::Flattened<Mesh> flat(mesh);
  auto soup = flat.make();
  std::vector<uint32_t> fixed;
  auto fix = [&](OpenMesh::VertexHandle vh) {
    if (!vh.is_valid() || static_cast<size_t>(vh.idx()) >= flat.compact_vertex.size() ||
        flat.compact_vertex[vh.idx()] < 0)
      throw Error(SURFKIT_INVALID_INPUT, "surfkit::fair: fixed vertex " + std::to_string(vh.idx()) +
                                             " is not a vertex of the mesh");
    fixed.push_back(static_cast<uint32_t>(flat.compact_vertex[vh.idx()]));
  };
  for (auto vh : options.fixed) fix(vh);
  OpenMesh::VPropHandleT<bool> marked;
  bool has_marked = !options.fixed_property.empty() && mesh.get_property_handle(marked, options.fixed_property);
  for (auto vh : mesh.vertices()) {
    bool locked = mesh.has_vertex_status() && mesh.status(vh).locked();
    if (locked || (has_marked && mesh.property(marked, vh))) fix(vh);
  }
  SurfkitFairOptions o{};
  detail::check(surfkit_fair_options_default(&o));
  o.boundary_rings = options.boundary_rings;
  o.max_refinements = 0;
  o.surface = options.surface;
  if (options.surface == SURFKIT_SURFACE_CATMULL_CLARK) o.c_special = 0.01;
  if (options.relative_gradient != 0) o.relative_gradient = options.relative_gradient;
  if (options.max_iterations != 0) o.max_iterations = options.max_iterations;
  if (options.isolation != 0) o.isolation = options.isolation;
  if (options.nodes != 0) o.nodes = options.nodes;
  if (options.c_special != 0) o.c_special = options.c_special;
  if (options.regularization != 0) o.regularization = options.regularization;
  o.method = options.method;
  o.coarse_start = options.coarse_start ? 1 : 0;
  o.fixed = fixed.data();
  o.fixed_count = fixed.size();
  detail::ProgressBridge bridge{&options.progress, nullptr};
  if (options.progress) {
    o.callback = &detail::ProgressBridge::call;
    o.user_data = &bridge;
  }
  SurfkitMesh* out = nullptr;
  SurfkitFairReport* raw_ptr = nullptr;
  int status = surfkit_fair(soup.get(), &o, &out, &raw_ptr);
  detail::MeshPtr optimized(out);
  std::unique_ptr<SurfkitFairReport, detail::FairReportFree> raw(raw_ptr);
  if (bridge.error) std::rethrow_exception(bridge.error);
  detail::check(status);
  SurfkitFairSummary s{};
  detail::check(surfkit_fair_report_summary(raw.get(), &s));
  const double* positions = nullptr;
  detail::check(surfkit_mesh_arrays(optimized.get(), &positions, nullptr, nullptr));
  using Scalar = typename Mesh::Point::value_type;
  for (size_t v = 0; v < flat.vertex_of.size(); ++v)
    mesh.set_point(flat.vertex_of[v], typename Mesh::Point(static_cast<Scalar>(positions[3 * v]),
                                                           static_cast<Scalar>(positions[3 * v + 1]),
                                                           static_cast<Scalar>(positions[3 * v + 2])));
  detail::update_normals(mesh);
  FairReport r;
  r.converged = s.converged != 0;
  r.cancelled = s.cancelled != 0;
  r.iterations = s.iterations;
  r.hessian_evaluations = s.hessian_evaluations;
  r.free_vertices = s.free_vertices;
  r.s_before = s.s_before;
  r.s_after = s.s_after;
  r.f_before = s.f_before;
  r.f_after = s.f_after;
  r.q_before = s.q_before;
  r.q_after = s.q_after;
  r.gradient_norm_before = s.gradient_norm_before;
  r.gradient_norm_after = s.gradient_norm_after;
  r.stalled = s.stalled != 0;
  r.coordinate_floor = s.coordinate_floor;
  r.surface = s.surface;
  r.method = s.method;
  r.coarse_stage = s.coarse_stage != 0;
  r.coarse_start_used = s.coarse_start_used != 0;
  const char* json = nullptr;
  detail::check(surfkit_fair_report_json(raw.get(), &json));
  r.json = json;
  return r;
}

// ---------------------------------------------------------------------------------------
// Splines: smoothing fit of scattered data and hole filling (Kouibia & Pasadas)

/// Options of fit(): the defaults of `surfkit fit`.
struct FitOptions {
  int space = SURFKIT_SPACE_BIQUADRATIC;
  unsigned cells_u = 8, cells_v = 8;
  double epsilon = 1e-9;
  int hole = SURFKIT_HOLE_NONE;
  std::vector<std::array<double, 2>> hole_polygon;
  std::array<double, 5> hole_ellipse{};  // cu, cv, a, b, level
  bool exact_c1 = false;
  /// Shape-preserving filling (2024, SURFKIT_SPACE_BFS_C1): component (0 x, 1 y, 2 z;
  /// −1 none) and the conditions (+1 ≥ 0 / increasing, −1 ≤ 0 / decreasing, 0 none).
  int shape_component = -1;
  int shape_value = 0, shape_slope_u = 0, shape_slope_v = 0;
  unsigned shape_lattice = 0;
  std::vector<std::array<double, 2>> shape_points;
};

/// A solved spline: evaluate σ at (u, v) in the data's parameter rectangle.
class Spline {
 public:
  explicit Spline(SurfkitSpline* s) : spline_(s) {}
  std::array<double, 3> evaluate(double u, double v) const {
    double uv[2] = {u, v};
    std::array<double, 3> xyz{};
    detail::check(surfkit_spline_evaluate(spline_.get(), 1, uv, xyz.data()));
    return xyz;
  }
  /// The fit's report (misfit, cells, the fill's constraints) as JSON.
  std::string report_json() const {
    const char* json = nullptr;
    detail::check(surfkit_spline_report_json(spline_.get(), &json));
    return json;
  }

 private:
  std::unique_ptr<SurfkitSpline, detail::SplineFree> spline_;
};

/// Fits the smoothing spline to data points (u, v) → (x, y, z) and fills the hole the
/// options name.
inline Spline fit(const std::vector<std::array<double, 2>>& uv, const std::vector<std::array<double, 3>>& xyz,
                  const FitOptions& options = FitOptions{}) {
  if (uv.size() != xyz.size())
    throw Error(SURFKIT_INVALID_INPUT, "surfkit::fit: " + std::to_string(uv.size()) + " parameters for " +
                                           std::to_string(xyz.size()) + " points");
  SurfkitFitOptions o{};
  detail::check(surfkit_fit_options_default(&o));
  o.space = options.space;
  o.cells_u = options.cells_u;
  o.cells_v = options.cells_v;
  o.epsilon = options.epsilon;
  o.hole = options.hole;
  o.hole_polygon = options.hole_polygon.empty() ? nullptr : options.hole_polygon.front().data();
  o.hole_polygon_count = options.hole_polygon.size();
  for (int k = 0; k < 5; ++k) o.hole_ellipse[k] = options.hole_ellipse[k];
  o.exact_c1 = options.exact_c1 ? 1 : 0;
  o.shape_component = options.shape_component;
  o.shape_value = options.shape_value;
  o.shape_slope_u = options.shape_slope_u;
  o.shape_slope_v = options.shape_slope_v;
  o.shape_lattice = options.shape_lattice;
  o.shape_points = options.shape_points.empty() ? nullptr : options.shape_points.front().data();
  o.shape_point_count = options.shape_points.size();
  SurfkitSpline* out = nullptr;
  detail::check(surfkit_fit(uv.empty() ? nullptr : uv.front().data(), xyz.empty() ? nullptr : xyz.front().data(),
                            uv.size(), &o, &out));
  return Spline(out);
}

}  // namespace surfkit

#endif  // SURFKIT_OPENMESH_HH
