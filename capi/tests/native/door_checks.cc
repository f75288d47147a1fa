// Checks of the C and C++ doors that need a native program (run by capi/tests/cpp_door.rs,
// also under AddressSanitizer + LeakSanitizer): bad input gets a status and a message
// naming the element, never an abort; a throwing progress callback is rethrown, a
// cancelling one stops the run; 1000 create/free cycles of every handle leak nothing; the
// process's memory limit is set, enforced (also on the EAT registry's vertex ids) and
// restored; EatCompanion keeps degenerate facets from OpenMesh; a whole-mesh test point; a
// failed call clears its outputs; surfkit_mesh_new checks its offsets against index_count;
// EatReport has the JSON report's counts; fair() leaves the mesh's normals up to date.
// Prints "ok: N checks" and exits 0, or names the failed check and exits 1.
#include <surfkit/openmesh.hh>

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

using Mesh = OpenMesh::PolyMesh_ArrayKernelT<>;

static int checks = 0;

#define EXPECT(condition)                                                             \
  do {                                                                                \
    ++checks;                                                                         \
    if (!(condition)) {                                                               \
      std::cerr << "check failed at line " << __LINE__ << ": " #condition << "\n";     \
      std::exit(1);                                                                   \
    }                                                                                 \
  } while (0)

static bool says(const char* part) { return std::strstr(surfkit_last_error(), part) != nullptr; }

/// An (n+1) × (n+1) grid of quads in the plane z = bump · x(1 − x) y(1 − y).
static Mesh grid(int n, float bump) {
  Mesh m;
  std::vector<Mesh::VertexHandle> v;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      float x = float(i) / n, y = float(j) / n;
      v.push_back(m.add_vertex(Mesh::Point(x, y, bump * x * (1 - x) * y * (1 - y))));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      m.add_face({v[j * (n + 1) + i], v[j * (n + 1) + i + 1], v[(j + 1) * (n + 1) + i + 1], v[(j + 1) * (n + 1) + i]});
  return m;
}

/// A cube of 6 quads (closed).
/// The saddle z = xy sampled on a 10 × 10 grid of [0, 1]²: (u, v) = (x, y).
static void saddle_samples(std::vector<double>& uv, std::vector<double>& xyz) {
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 10; ++i) {
      double x = i / 9.0, y = j / 9.0;
      uv.insert(uv.end(), {x, y});
      xyz.insert(xyz.end(), {x, y, x * y});
    }
}

static void cube(std::vector<double>& p, std::vector<uint32_t>& o, std::vector<uint32_t>& idx) {
  p = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  idx = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
  o = {0, 4, 8, 12, 16, 20, 24};
}

static void bad_input() {
  SurfkitMesh* m = nullptr;
  std::vector<double> p;
  std::vector<uint32_t> o, idx;
  cube(p, o, idx);
  EXPECT(surfkit_mesh_new(nullptr, 8, o.data(), 6, idx.data(), idx.size(), &m) == SURFKIT_INVALID_INPUT && says("positions"));
  EXPECT(m == nullptr);
  EXPECT(surfkit_mesh_new(p.data(), 8, o.data(), 6, idx.data(), idx.size(), nullptr) == SURFKIT_INVALID_INPUT && says("out"));
  std::vector<uint32_t> wrong = idx;
  wrong[5] = 99;
  EXPECT(surfkit_mesh_new(p.data(), 8, o.data(), 6, wrong.data(), wrong.size(), &m) == SURFKIT_INVALID_INPUT &&
         says("face 1 refers to vertex 99"));
  std::vector<double> nan = p;
  nan[7] = std::numeric_limits<double>::quiet_NaN();
  EXPECT(surfkit_mesh_new(nan.data(), 8, o.data(), 6, idx.data(), idx.size(), &m) == SURFKIT_INVALID_INPUT &&
         says("vertex 2 has a non-finite coordinate"));
  std::vector<uint32_t> decreasing = {0, 4, 2, 12, 16, 20, 24};
  EXPECT(surfkit_mesh_new(p.data(), 8, decreasing.data(), 6, idx.data(), idx.size(), &m) == SURFKIT_INVALID_INPUT &&
         says("decrease at face 1"));
  EXPECT(surfkit_mesh_read("/nonexistent/surfkit.obj", &m) == SURFKIT_IO && says("/nonexistent/surfkit.obj"));
  SurfkitEatReport* r = nullptr;
  EXPECT(surfkit_eat_scan(nullptr, nullptr, &r) == SURFKIT_INVALID_INPUT && says("mesh is a null pointer"));

  EXPECT(surfkit_mesh_new(p.data(), 8, o.data(), 6, idx.data(), idx.size(), &m) == SURFKIT_OK);
  EXPECT(std::strlen(surfkit_last_error()) == 0);
  EXPECT(surfkit_eat_scan(m, nullptr, &r) == SURFKIT_OK);
  SurfkitFlaw f;
  EXPECT(surfkit_eat_report_flaw(r, 0, &f) == SURFKIT_INVALID_INPUT && says("flaw 0 out of range"));
  surfkit_eat_report_free(r);

  // A closed mesh with nothing fixed: the paper's c is undefined.
  SurfkitMesh* faired = nullptr;
  EXPECT(surfkit_fair(m, nullptr, &faired, nullptr) != SURFKIT_OK && std::strlen(surfkit_last_error()) > 0);
  EXPECT(faired == nullptr);

  SurfkitLimit* limit = nullptr;
  EXPECT(surfkit_limit_new(m, nullptr, 4, &limit) == SURFKIT_OK);
  uint32_t ptex = 6;
  double u = 0.5, v = 0.5, d[30];
  EXPECT(surfkit_limit_evaluate(limit, 1, &ptex, &u, &v, d) == SURFKIT_INVALID_INPUT && says("ptex face 6 out of range"));
  ptex = 0;
  u = 2.0;
  EXPECT(surfkit_limit_evaluate(limit, 1, &ptex, &u, &v, d) == SURFKIT_INVALID_INPUT && says("outside [0, 1]"));
  surfkit_limit_free(limit);
  EXPECT(surfkit_limit_new(m, nullptr, 11, &limit) == SURFKIT_INVALID_INPUT && says("max_isolation 11"));
  EXPECT(limit == nullptr);
  surfkit_mesh_free(m);

  SurfkitRegistry* reg = nullptr;
  EXPECT(surfkit_registry_new(3, &reg) == SURFKIT_OK);
  uint32_t tri[3] = {0, 1, 7};
  EXPECT(surfkit_registry_add_facet(reg, tri, 3, 0, nullptr) == SURFKIT_INVALID_INPUT && says("vertex 7"));
  surfkit_registry_free(reg);

  double uv[2] = {0, 0}, xyz[3] = {0, 0, std::numeric_limits<double>::infinity()};
  SurfkitSpline* s = nullptr;
  EXPECT(surfkit_fit(uv, xyz, 1, nullptr, &s) == SURFKIT_INVALID_INPUT && says("data point 0"));
  SurfkitFitOptions huge;
  surfkit_fit_options_default(&huge);
  huge.cells_u = huge.cells_v = 1000000;
  xyz[2] = 0;
  EXPECT(surfkit_fit(uv, xyz, 1, &huge, &s) == SURFKIT_INVALID_INPUT && says("cells are supported"));

  // The C++ layer throws surfkit::Error with the same message.
  Mesh closed;
  {
    std::vector<Mesh::VertexHandle> h;
    for (int k = 0; k < 8; ++k) h.push_back(closed.add_vertex(Mesh::Point(float(p[3 * k]), float(p[3 * k + 1]), float(p[3 * k + 2]))));
    for (int k = 0; k < 6; ++k) closed.add_face({h[idx[4 * k]], h[idx[4 * k + 1]], h[idx[4 * k + 2]], h[idx[4 * k + 3]]});
  }
  bool thrown = false;
  try {
    surfkit::fair(closed);
  } catch (const surfkit::Error& e) {
    thrown = e.status() != SURFKIT_OK && std::string(e.what()).size() > 0;
  }
  EXPECT(thrown);

  // A facet OpenMesh refuses (a third facet on one edge) is registered all the same.
  Mesh fan;
  surfkit::EatCompanion<Mesh> companion(fan);
  std::vector<Mesh::VertexHandle> v5;
  for (int k = 0; k < 5; ++k) v5.push_back(fan.add_vertex(Mesh::Point(float(k), float(k % 2), 0)));
  EXPECT(companion.add_face({v5[0], v5[1], v5[2]}).is_valid());
  EXPECT(companion.add_face({v5[1], v5[0], v5[3]}).is_valid());
  EXPECT(!companion.add_face({v5[0], v5[1], v5[4]}).is_valid());
  EXPECT(companion.refusals().size() == 1 && companion.refusals()[0].facet == 2);
  EXPECT(companion.refusals()[0].message.find("complex edge") != std::string::npos);
  auto c = companion.checkpoint(1);
  EXPECT(c.facets == 3 && c.edges == 7 && c.vertices == 5 && c.euler_characteristic == 1 && c.verified);
}

/// A stand-in for a pointer an earlier call left in an output: a failed call must not leave
/// it there (nor leave the slot untouched).
template <class T>
static T* stale() {
  static char storage[64];
  return reinterpret_cast<T*>(storage);
}

static bool all_nan(const double* x, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (!std::isnan(x[i])) return false;
  return true;
}

/// A failed call sets every output it was given to its empty value (header: handles and
/// pointers NULL, counts and structs zero, the registry's facet UINT32_MAX, result arrays
/// NaN), so a caller that does not check the status finds no stale pointer or number.
static void failed_calls_clear_outputs() {
  std::vector<double> p;
  std::vector<uint32_t> o, idx;
  cube(p, o, idx);
  SurfkitMesh* m = stale<SurfkitMesh>();
  EXPECT(surfkit_mesh_new(nullptr, 8, o.data(), 6, idx.data(), idx.size(), &m) == SURFKIT_INVALID_INPUT);
  EXPECT(m == nullptr);
  m = stale<SurfkitMesh>();
  EXPECT(surfkit_mesh_read("/nonexistent/surfkit.obj", &m) == SURFKIT_IO && m == nullptr);
  size_t nv = 7, nf = 7, ni = 7;
  EXPECT(surfkit_mesh_counts(nullptr, &nv, &nf, &ni) == SURFKIT_INVALID_INPUT && nv == 0 && nf == 0 && ni == 0);
  const double* pp = stale<const double>();
  const uint32_t* po = stale<const uint32_t>();
  const uint32_t* pi = stale<const uint32_t>();
  EXPECT(surfkit_mesh_arrays(nullptr, &pp, &po, &pi) == SURFKIT_INVALID_INPUT);
  EXPECT(pp == nullptr && po == nullptr && pi == nullptr);

  // The EAT: a scan refused for its options, and the accessors of a live report asked
  // for what it does not have (after a successful call filled the same outputs).
  EXPECT(surfkit_mesh_new(p.data(), 8, o.data(), 6, idx.data(), idx.size(), &m) == SURFKIT_OK);
  SurfkitEatOptions eo{};
  EXPECT(surfkit_eat_options_default(&eo) == SURFKIT_OK);
  eo.weld_tolerance = -1;
  SurfkitEatReport* r = stale<SurfkitEatReport>();
  EXPECT(surfkit_eat_scan(m, &eo, &r) == SURFKIT_INVALID_INPUT && says("weld_tolerance") && r == nullptr);
  const int64_t chi = 2;
  eo.weld_tolerance = 0;
  eo.test_point_expected = &chi;
  eo.test_point_count = 1;
  EXPECT(surfkit_eat_scan(m, &eo, &r) == SURFKIT_OK && r != nullptr);
  SurfkitEatCounts counts{};
  EXPECT(surfkit_eat_report_counts(r, &counts) == SURFKIT_OK && counts.faces == 6);
  EXPECT(surfkit_eat_report_counts(nullptr, &counts) == SURFKIT_INVALID_INPUT);
  EXPECT(counts.faces == 0 && counts.vertices == 0 && counts.euler_characteristic == 0 && counts.genus == 0);
  size_t points = 0;
  SurfkitTestPoint t{};
  EXPECT(surfkit_eat_report_test_point(r, 0, &points, &t) == SURFKIT_OK && points == 1 && t.facets == 6);
  EXPECT(surfkit_eat_report_test_point(r, 1, &points, &t) == SURFKIT_INVALID_INPUT && says("test point 1"));
  EXPECT(points == 0 && t.facets == 0 && t.expected_euler_characteristic == 0 && t.verified == 0);
  size_t flaws = 9;
  EXPECT(surfkit_eat_report_flaw_count(nullptr, &flaws) == SURFKIT_INVALID_INPUT && flaws == 0);
  SurfkitFlaw f;
  f.kind = stale<const char>();
  f.vertices = stale<const uint32_t>();
  f.vertex_count = 3;
  f.faces = stale<const uint32_t>();
  f.face_count = 2;
  f.description = f.suggested_fix = stale<const char>();
  EXPECT(surfkit_eat_report_flaw(r, 0, &f) == SURFKIT_INVALID_INPUT && says("flaw 0 out of range"));
  EXPECT(f.kind == nullptr && f.vertices == nullptr && f.vertex_count == 0 && f.faces == nullptr &&
         f.face_count == 0 && f.description == nullptr && f.suggested_fix == nullptr);
  const char* json = stale<const char>();
  EXPECT(surfkit_eat_report_json(nullptr, &json) == SURFKIT_INVALID_INPUT && json == nullptr);
  surfkit_eat_report_free(r);
  // Test points short of the face count are checked where given: the cube's bottom and top
  // (V 8, E 8, F 2: χ 2), then a side (E 10, F 3: χ 1); the whole mesh is not checked.
  const size_t stage_facets[] = {2, 3};
  const int64_t stage_chi[] = {2, 1};
  eo.test_point_facets = stage_facets;
  eo.test_point_expected = stage_chi;
  eo.test_point_count = 2;
  EXPECT(surfkit_eat_scan(m, &eo, &r) == SURFKIT_OK && r != nullptr);
  EXPECT(surfkit_eat_report_test_point(r, 1, &points, &t) == SURFKIT_OK && points == 2 && t.facets == 3 &&
         t.expected_euler_characteristic == 1 && t.euler_characteristic == 1 && t.verified == 1);
  surfkit_eat_report_free(r);

  // Fairing: a closed mesh with nothing fixed is refused; both outputs are cleared.
  SurfkitMesh* faired = stale<SurfkitMesh>();
  SurfkitFairReport* fr = stale<SurfkitFairReport>();
  EXPECT(surfkit_fair(m, nullptr, &faired, &fr) != SURFKIT_OK && faired == nullptr && fr == nullptr);
  SurfkitFairSummary summary;
  summary.iterations = 5;
  summary.f_after = 1.5;
  EXPECT(surfkit_fair_report_summary(nullptr, &summary) == SURFKIT_INVALID_INPUT);
  EXPECT(summary.iterations == 0 && summary.f_after == 0);
  json = stale<const char>();
  EXPECT(surfkit_fair_report_json(nullptr, &json) == SURFKIT_INVALID_INPUT && json == nullptr);

  // Subdivision and the limit surface.
  SurfkitMesh* fine = stale<SurfkitMesh>();
  EXPECT(surfkit_subdivide(m, 11, nullptr, &fine) == SURFKIT_INVALID_INPUT && fine == nullptr);
  SurfkitLimit* limit = stale<SurfkitLimit>();
  EXPECT(surfkit_limit_new(m, nullptr, 0, &limit) == SURFKIT_INVALID_INPUT && limit == nullptr);
  EXPECT(surfkit_limit_new(m, nullptr, 4, &limit) == SURFKIT_OK);
  uint32_t first = 3, count = 1;
  EXPECT(surfkit_limit_ptex_faces(limit, 6, &first, &count) == SURFKIT_INVALID_INPUT && first == 0 && count == 0);
  EXPECT(surfkit_limit_ptex_faces(limit, 2, &first, &count) == SURFKIT_OK && first == 2 && count == 1);
  EXPECT(surfkit_limit_ptex_faces(limit, 2, &first, nullptr) == SURFKIT_INVALID_INPUT && first == 0);
  uint32_t ptex[2] = {0, 6};
  double u[2] = {0.5, 0.5}, v[2] = {0.5, 0.5}, d[60];
  std::fill(d, d + 60, 1.0);
  EXPECT(surfkit_limit_evaluate(limit, 1, ptex, u, v, d) == SURFKIT_OK && !std::isnan(d[0]) && d[30] == 1.0);
  EXPECT(surfkit_limit_evaluate(limit, 2, ptex, u, v, d) == SURFKIT_INVALID_INPUT && all_nan(d, 60));
  double normals[6] = {1, 1, 1, 1, 1, 1}, mean[2] = {1, 1}, k2[2] = {1, 1};
  EXPECT(surfkit_limit_curvature(limit, 2, ptex, u, v, normals, mean, nullptr, nullptr, k2) == SURFKIT_INVALID_INPUT);
  EXPECT(all_nan(normals, 6) && all_nan(mean, 2) && all_nan(k2, 2));
  surfkit_limit_free(limit);
  surfkit_mesh_free(m);

  // The registry.
  SurfkitRegistry* reg = nullptr;
  EXPECT(surfkit_registry_new(3, &reg) == SURFKIT_OK);
  uint32_t facet = 5;
  const uint32_t tri[3] = {0, 1, 2}, far[3] = {0, 1, 9};
  EXPECT(surfkit_registry_add_facet(reg, tri, 3, 0, &facet) == SURFKIT_OK && facet == 0);
  EXPECT(surfkit_registry_add_facet(reg, far, 3, 1, &facet) == SURFKIT_INVALID_INPUT && facet == UINT32_MAX);
  SurfkitCheckpoint cp{};
  EXPECT(surfkit_registry_checkpoint(reg, 2, &cp) == SURFKIT_OK && !cp.verified && cp.statistics.facets == 1);
  EXPECT(surfkit_registry_checkpoint(nullptr, 2, &cp) == SURFKIT_INVALID_INPUT);
  EXPECT(cp.statistics.facets == 0 && cp.expected_euler_characteristic == 0);
  SurfkitEatStatistics st{};
  EXPECT(surfkit_registry_statistics(reg, &st) == SURFKIT_OK && st.facets == 1);
  EXPECT(surfkit_registry_statistics(nullptr, &st) == SURFKIT_INVALID_INPUT && st.facets == 0 && st.vertices == 0);
  const uint32_t* suspects = stale<const uint32_t>();
  size_t suspect_count = 4;
  EXPECT(surfkit_registry_suspects(nullptr, &suspects, &suspect_count) == SURFKIT_INVALID_INPUT);
  EXPECT(suspects == nullptr && suspect_count == 0);
  suspects = stale<const uint32_t>();
  EXPECT(surfkit_registry_suspects(reg, &suspects, nullptr) == SURFKIT_INVALID_INPUT && suspects == nullptr);
  surfkit_registry_free(reg);

  // Splines.
  double data_uv[2] = {0, 0}, data_xyz[3] = {0, 0, std::numeric_limits<double>::quiet_NaN()};
  SurfkitSpline* s = stale<SurfkitSpline>();
  EXPECT(surfkit_fit(data_uv, data_xyz, 1, nullptr, &s) == SURFKIT_INVALID_INPUT && s == nullptr);
  std::vector<double> grid_uv, grid_xyz;
  saddle_samples(grid_uv, grid_xyz);
  SurfkitFitOptions fit;
  surfkit_fit_options_default(&fit);
  fit.cells_u = fit.cells_v = 2;
  EXPECT(surfkit_fit(grid_uv.data(), grid_xyz.data(), 100, &fit, &s) == SURFKIT_OK);
  double at[4] = {0.5, 0.5, 2.0, 0.5}, xyz[6] = {1, 1, 1, 1, 1, 1};
  EXPECT(surfkit_spline_evaluate(s, 2, at, xyz) == SURFKIT_INVALID_INPUT && says("point 1") && all_nan(xyz, 6));
  EXPECT(surfkit_spline_evaluate(s, 1, at, xyz) == SURFKIT_OK && std::abs(xyz[2] - 0.25) < 1e-6);
  json = stale<const char>();
  EXPECT(surfkit_spline_report_json(nullptr, &json) == SURFKIT_INVALID_INPUT && json == nullptr);
  surfkit_spline_free(s);
}

/// surfkit_mesh_new checks the offsets against index_count before it reads an index, and
/// the size of its copy against the memory limit before it reads anything: a wrong count
/// is an error naming the face, never a read past the caller's arrays.
static void mesh_new_checks_its_arrays() {
  std::vector<double> p;
  std::vector<uint32_t> o, idx;
  cube(p, o, idx);
  SurfkitMesh* m = nullptr;
  // The last offset must be the index count: one more announced, or one fewer.
  EXPECT(surfkit_mesh_new(p.data(), 8, o.data(), 6, idx.data(), 23, &m) == SURFKIT_INVALID_INPUT && m == nullptr);
  EXPECT(says("face 5 ends at face_offsets[6] = 24 but index_count is 23"));
  // A corrupt last offset (4 000 000 000 indices claimed) is caught without reading them.
  std::vector<uint32_t> huge_end = o;
  huge_end.back() = 4000000000u;
  EXPECT(surfkit_mesh_new(p.data(), 8, huge_end.data(), 6, idx.data(), idx.size(), &m) == SURFKIT_INVALID_INPUT);
  EXPECT(says("face 5 ends at face_offsets[6] = 4000000000 but index_count is 24") && m == nullptr);
  std::vector<uint32_t> late_start = o;
  late_start[0] = 1;
  EXPECT(surfkit_mesh_new(p.data(), 8, late_start.data(), 6, idx.data(), idx.size(), &m) == SURFKIT_INVALID_INPUT);
  EXPECT(says("face_offsets[0] is 1: face 0 must start at index 0"));
  std::vector<uint32_t> decreasing = {0, 4, 8, 12, 11, 20, 24};
  EXPECT(surfkit_mesh_new(p.data(), 8, decreasing.data(), 6, idx.data(), idx.size(), &m) == SURFKIT_INVALID_INPUT);
  EXPECT(says("face_offsets decrease at face 3: it starts at 12 and ends at 11"));
  // No face: the one offset is 0 and there is no index.
  const uint32_t zero = 0, one = 1;
  EXPECT(surfkit_mesh_new(p.data(), 8, &one, 0, nullptr, 0, &m) == SURFKIT_INVALID_INPUT && says("face_offsets[0] is 1"));
  EXPECT(surfkit_mesh_new(p.data(), 8, &zero, 0, nullptr, 0, &m) == SURFKIT_OK);
  size_t nv = 0, nf = 9, ni = 9;
  EXPECT(surfkit_mesh_counts(m, &nv, &nf, &ni) == SURFKIT_OK && nv == 8 && nf == 0 && ni == 0);
  surfkit_mesh_free(m);
  // Degenerate facets (2 corners, 1 corner) are taken: the EAT counts them.
  const uint32_t short_offsets[4] = {0, 3, 5, 6}, short_faces[6] = {0, 1, 2, 2, 3, 4};
  m = nullptr;
  EXPECT(surfkit_mesh_new(p.data(), 8, short_offsets, 3, short_faces, 6, &m) == SURFKIT_OK);
  SurfkitEatReport* r = nullptr;
  EXPECT(surfkit_eat_scan(m, nullptr, &r) == SURFKIT_OK);
  SurfkitEatCounts c{};
  EXPECT(surfkit_eat_report_counts(r, &c) == SURFKIT_OK && c.faces == 3 && c.degenerate_facets == 2);
  surfkit_eat_report_free(r);
  surfkit_mesh_free(m);
  // A size past the memory limit is refused before the arrays are read: the positions
  // announced here (2²⁰ vertices, 24 MiB to copy) do not exist.
  EXPECT(surfkit_set_max_memory(uint64_t(16) << 20) == SURFKIT_OK);
  m = stale<SurfkitMesh>();
  EXPECT(surfkit_mesh_new(p.data(), size_t(1) << 20, o.data(), 6, idx.data(), idx.size(), &m) == SURFKIT_RESOURCE_LIMIT);
  EXPECT(m == nullptr && says("1048576 vertices, 6 faces and 24 face indices") && says("memory limit of 16 MiB"));
  EXPECT(surfkit_mesh_new(p.data(), 8, o.data(), SIZE_MAX / 8, idx.data(), idx.size(), &m) == SURFKIT_RESOURCE_LIMIT);
  EXPECT(surfkit_set_max_memory(0) == SURFKIT_OK);
}

/// A soup through the C door's scan, read back as the C++ layer's EatReport.
static surfkit::EatReport eat_soup(const std::vector<double>& p, const std::vector<uint32_t>& o,
                                   const std::vector<uint32_t>& idx) {
  SurfkitMesh* m = nullptr;
  EXPECT(surfkit_mesh_new(p.data(), p.size() / 3, o.data(), o.size() - 1, idx.data(), idx.size(), &m) == SURFKIT_OK);
  SurfkitEatReport* raw = nullptr;
  EXPECT(surfkit_eat_scan(m, nullptr, &raw) == SURFKIT_OK);
  surfkit::EatReport r = surfkit::detail::read_eat_report(raw);
  surfkit_eat_report_free(raw);
  surfkit_mesh_free(m);
  return r;
}

static bool json_has(const surfkit::EatReport& r, const std::string& pair) {
  return r.json.find(pair) != std::string::npos;
}

/// EatReport carries every count of the JSON report (report.counts, and the refused faces
/// of report.halfedge): the values equal the JSON's.
static void eat_report_has_the_json_counts() {
  // Two triangles running edge 1–2 the same way (OpenMesh refuses the second) and a vertex
  // no face uses.
  surfkit::EatReport r = eat_soup({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 5, 5, 5}, {0, 3, 6}, {0, 1, 2, 1, 2, 3});
  EXPECT(r.vertices_in_file == 5 && json_has(r, "\"vertices_in_file\":5"));
  EXPECT(r.vertices == 4 && json_has(r, "\"vertices_referenced\":4"));
  EXPECT(r.inconsistent_orientation_edges == 1 && json_has(r, "\"inconsistent_orientation_edges\":1"));
  EXPECT(r.refused_faces == 1 && json_has(r, "\"refused\":[[1,"));
  EXPECT(r.boundary_loops_walk == -1 && json_has(r, "\"boundary_loops_walk\":null"));
  EXPECT(r.non_orientable_genus == -1 && json_has(r, "\"non_orientable_genus\":null"));
  // Two triangles sharing only vertex 0: one boundary graph, two loops walked fan by fan.
  r = eat_soup({0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0}, {0, 3, 6}, {0, 1, 2, 0, 3, 4});
  EXPECT(r.boundary_loops == 1 && json_has(r, "\"boundary_loops\":1"));
  EXPECT(r.boundary_loops_walk == 2 && json_has(r, "\"boundary_loops_walk\":2"));
  EXPECT(r.vertices_in_file == 5 && r.inconsistent_orientation_edges == 0 && r.refused_faces == 0);
  // A Möbius strip of four quads (the last one twisted): one cross-cap.
  std::vector<double> p;
  for (int i = 0; i < 4; ++i) p.insert(p.end(), {double(i), 0.0, 1.0});  // t0..t3
  for (int i = 0; i < 4; ++i) p.insert(p.end(), {double(i), 0.5, 0.0});  // b0..b3
  r = eat_soup(p, {0, 4, 8, 12, 16}, {0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 4, 0, 7});
  EXPECT(r.euler_characteristic == 0 && r.boundary_loops == 1);
  EXPECT(r.non_orientable_genus == 1 && json_has(r, "\"non_orientable_genus\":1"));
  EXPECT(r.genus == -1 && json_has(r, "\"genus\":null"));
  EXPECT(r.inconsistent_orientation_edges == 1 && r.refused_faces == 1);
  // Through eat(mesh): an OpenMesh grid with a vertex of its own.
  Mesh m = grid(4, 0.5f);
  m.add_vertex(Mesh::Point(9, 9, 9));
  r = surfkit::eat(m);
  EXPECT(r.vertices_in_file == 26 && r.vertices == 25 && r.unreferenced_vertices == 1);
  EXPECT(r.boundary_loops_walk == 1 && json_has(r, "\"boundary_loops_walk\":1"));
  EXPECT(r.refused_faces == 0 && r.inconsistent_orientation_edges == 0 && r.non_orientable_genus == -1);
}

/// fair() writes new points and then the normals the mesh has are those OpenMesh computes
/// from them (not the stale ones of the old points), for every combination of normals.
static void fair_updates_the_normals() {
  for (int variant = 0; variant < 3; ++variant) {
    Mesh m = grid(6, 1.0f);
    const bool faces = variant != 1, vertices = variant != 2;
    if (faces) m.request_face_normals();
    if (vertices) m.request_vertex_normals();
    if (variant == 0) m.request_halfedge_normals();
    m.update_normals();
    if (!faces)  // vertex normals only: OpenMesh's update_normals() leaves them; set them
      for (auto vh : m.vertices()) m.set_normal(vh, Mesh::Normal(0, 0, 1));
    const Mesh before = m;
    surfkit::FairOptions options;
    options.boundary_rings = 1;
    surfkit::FairReport q = surfkit::fair(m, options);
    EXPECT(q.converged && q.s_after < q.s_before);
    EXPECT(m.has_face_normals() == faces && m.has_vertex_normals() == vertices);
    // What OpenMesh computes from the new points.
    Mesh expected = m;
    expected.request_face_normals();
    expected.update_normals();
    size_t moved = 0;
    if (faces)
      for (auto fh : m.faces()) {
        EXPECT(m.normal(fh) == expected.normal(fh));
        moved += m.normal(fh) != before.normal(fh);
      }
    if (vertices)
      for (auto vh : m.vertices()) {
        EXPECT(m.normal(vh) == expected.normal(vh));
        moved += m.normal(vh) != before.normal(vh);
      }
    if (variant == 0)
      for (auto hh : m.halfedges()) EXPECT(m.normal(hh) == expected.normal(hh));
    EXPECT(moved > 10);
  }
}

static void callbacks() {
  // A throwing progress callback: the exception reaches the caller, nothing aborts.
  Mesh m = grid(6, 1.0f);
  surfkit::FairOptions options;
  options.boundary_rings = 1;
  options.progress = [](const surfkit::FairIteration&) -> bool { throw std::runtime_error("from the callback"); };
  bool rethrown = false;
  try {
    surfkit::fair(m, options);
  } catch (const std::runtime_error& e) {
    rethrown = std::string(e.what()) == "from the callback";
  }
  EXPECT(rethrown);
  // A cancelling callback stops after the iteration it was told about.
  size_t seen = 0;
  options.progress = [&](const surfkit::FairIteration& it) { seen = it.iteration; return it.iteration < 2; };
  Mesh again = grid(6, 1.0f);
  surfkit::FairReport q = surfkit::fair(again, options);
  EXPECT(q.cancelled && !q.converged && q.iterations == 2 && seen == 2 && q.surface == SURFKIT_SURFACE_G2);
}

static void cycles() {
  std::vector<double> p;
  std::vector<uint32_t> o, idx;
  cube(p, o, idx);
  Mesh plate = grid(4, 1.0f);
  std::vector<double> uv, xyz;
  saddle_samples(uv, xyz);
  SurfkitFitOptions fit;
  surfkit_fit_options_default(&fit);
  fit.cells_u = fit.cells_v = 2;
  for (int k = 0; k < 1000; ++k) {
    SurfkitMesh* m = nullptr;
    EXPECT(surfkit_mesh_new(p.data(), 8, o.data(), 6, idx.data(), idx.size(), &m) == SURFKIT_OK);
    SurfkitEatReport* r = nullptr;
    EXPECT(surfkit_eat_scan(m, nullptr, &r) == SURFKIT_OK);
    const char* json = nullptr;
    EXPECT(surfkit_eat_report_json(r, &json) == SURFKIT_OK && json[0] == '{');
    surfkit_eat_report_free(r);
    SurfkitMesh* fine = nullptr;
    EXPECT(surfkit_subdivide(m, 1, nullptr, &fine) == SURFKIT_OK);
    surfkit_mesh_free(fine);
    SurfkitLimit* limit = nullptr;
    EXPECT(surfkit_limit_new(m, nullptr, 2, &limit) == SURFKIT_OK);
    surfkit_limit_free(limit);
    surfkit_mesh_free(m);
    SurfkitRegistry* reg = nullptr;
    EXPECT(surfkit_registry_new(8, &reg) == SURFKIT_OK);
    EXPECT(surfkit_registry_add_facet(reg, idx.data(), 4, 0, nullptr) == SURFKIT_OK);
    SurfkitCheckpoint c;
    EXPECT(surfkit_registry_checkpoint(reg, 2, &c) == SURFKIT_OK && !c.verified);
    surfkit_registry_free(reg);
    SurfkitSpline* s = nullptr;
    EXPECT(surfkit_fit(uv.data(), xyz.data(), 100, &fit, &s) == SURFKIT_OK);
    surfkit_spline_free(s);
    // An error path allocates a message too.
    EXPECT(surfkit_mesh_new(nullptr, 8, o.data(), 6, idx.data(), idx.size(), &m) == SURFKIT_INVALID_INPUT);
  }
  // Fairing handles: a small plate, one iteration each.
  surfkit::detail::Flattened<Mesh> flat(plate);
  auto soup = flat.make();
  SurfkitFairOptions options;
  surfkit_fair_options_default(&options);
  options.boundary_rings = 1;
  options.max_iterations = 1;
  for (int k = 0; k < 1000; ++k) {
    SurfkitMesh* out = nullptr;
    SurfkitFairReport* report = nullptr;
    EXPECT(surfkit_fair(soup.get(), &options, &out, &report) == SURFKIT_OK);
    SurfkitFairSummary summary;
    EXPECT(surfkit_fair_report_summary(report, &summary) == SURFKIT_OK && summary.iterations == 1);
    surfkit_fair_report_free(report);
    surfkit_mesh_free(out);
  }
  // The surface option: the default is Kiciak's G² surface, the summary names the one
  // optimized, and an unknown surface is refused with a message.
  for (int surface : {SURFKIT_SURFACE_G2, SURFKIT_SURFACE_CATMULL_CLARK}) {
    options.surface = surface;
    SurfkitMesh* out = nullptr;
    SurfkitFairReport* report = nullptr;
    EXPECT(surfkit_fair(soup.get(), &options, &out, &report) == SURFKIT_OK);
    SurfkitFairSummary summary;
    EXPECT(surfkit_fair_report_summary(report, &summary) == SURFKIT_OK && summary.surface == surface);
    surfkit_fair_report_free(report);
    surfkit_mesh_free(out);
  }
  SurfkitFairOptions defaults;
  surfkit_fair_options_default(&defaults);
  EXPECT(defaults.surface == SURFKIT_SURFACE_G2);
  // The method option: by size by default (the plain method on this plate, which says
  // so); the multilevel method needs a coarser level, which the plate is not a refinement
  // of; an unknown method is refused with a message.
  EXPECT(defaults.method == SURFKIT_METHOD_AUTO);
  {
    SurfkitMesh* out = nullptr;
    SurfkitFairReport* report = nullptr;
    EXPECT(options.method == SURFKIT_METHOD_AUTO);
    EXPECT(surfkit_fair(soup.get(), &options, &out, &report) == SURFKIT_OK);
    SurfkitFairSummary summary;
    EXPECT(surfkit_fair_report_summary(report, &summary) == SURFKIT_OK &&
           summary.method == SURFKIT_METHOD_PLAIN);
    surfkit_fair_report_free(report);
    surfkit_mesh_free(out);
    SurfkitFairOptions multilevel = options;
    multilevel.method = SURFKIT_METHOD_MULTILEVEL;
    multilevel.max_refinements = 0;
    SurfkitMesh* none = nullptr;
    EXPECT(surfkit_fair(soup.get(), &multilevel, &none, nullptr) == SURFKIT_INVALID_INPUT &&
           std::strstr(surfkit_last_error(), "needs a coarser level") != nullptr && none == nullptr);
    multilevel.method = 9;
    EXPECT(surfkit_fair(soup.get(), &multilevel, &none, nullptr) == SURFKIT_INVALID_INPUT &&
           std::strstr(surfkit_last_error(), "method 9") != nullptr && none == nullptr);
  }
  options.surface = 7;
  SurfkitMesh* refused = nullptr;
  EXPECT(surfkit_fair(soup.get(), &options, &refused, nullptr) == SURFKIT_INVALID_INPUT &&
         std::strstr(surfkit_last_error(), "surface 7") != nullptr && refused == nullptr);
}

/// Float meshes: surfkit computes in double and rounds once into the float mesh.
static void float_traits() {
  struct DoubleTraits : public OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
  };
  using MeshD = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;
  Mesh f = grid(5, 2.0f);
  MeshD d;
  for (auto vh : f.vertices()) d.add_vertex(OpenMesh::Vec3d(f.point(vh)[0], f.point(vh)[1], f.point(vh)[2]));
  for (auto fh : f.faces()) {
    std::vector<MeshD::VertexHandle> c;
    for (auto vh : f.fv_range(fh)) c.push_back(d.vertex_handle(vh.idx()));
    d.add_face(c);
  }
  Mesh fine_f = surfkit::subdivide(f, 2);
  MeshD fine_d = surfkit::subdivide(d, 2);
  EXPECT(fine_f.n_vertices() == fine_d.n_vertices() && fine_f.n_faces() == fine_d.n_faces());
  for (auto vh : fine_d.vertices())
    for (int k = 0; k < 3; ++k) {
      double exact = fine_d.point(vh)[k];
      EXPECT(static_cast<float>(exact) == fine_f.point(fine_f.vertex_handle(vh.idx()))[k]);
    }
}

/// Deleted but not collected elements are skipped, and handles are the caller's.
static void deleted_elements() {
  Mesh m = grid(4, 0.5f);
  m.request_face_status();
  m.request_edge_status();
  m.request_vertex_status();
  Mesh collected = m;
  auto hole = m.face_handle(5);
  std::vector<int> rim_edges;
  for (auto eh : m.fe_range(hole)) rim_edges.push_back(eh.idx());
  std::sort(rim_edges.begin(), rim_edges.end());
  m.delete_face(hole, false);
  collected.delete_face(collected.face_handle(5), false);
  collected.garbage_collection();
  surfkit::EatReport a = surfkit::eat(m), b = surfkit::eat(collected);
  EXPECT(a.vertices == b.vertices && a.edges == b.edges && a.faces == b.faces && a.faces == 15);
  EXPECT(a.boundary_loops == 2 && b.boundary_loops == 2 && a.flaws.size() == b.flaws.size());
  for (const auto& flaw : a.flaws)
    for (auto fh : flaw.faces) EXPECT(!m.status(fh).deleted());
  // The opening's rim is the deleted face's four edges, as handles of `m`.
  bool rim = false;
  for (const auto& flaw : a.flaws) {
    std::vector<int> edges;
    for (auto eh : flaw.edges) edges.push_back(eh.idx());
    std::sort(edges.begin(), edges.end());
    rim = rim || edges == rim_edges;
  }
  EXPECT(rim);
}

/// The process's memory limit: set, refused below 1 MiB, enforced, restored.
static void memory_limit() {
  const uint64_t machine = surfkit_max_memory();
  EXPECT(machine >= (uint64_t(1) << 20));
  EXPECT(surfkit_set_max_memory(1000) == SURFKIT_INVALID_INPUT && says("1 MiB"));
  EXPECT(surfkit_max_memory() == machine);
  EXPECT(surfkit_set_max_memory(uint64_t(16) << 20) == SURFKIT_OK);
  EXPECT(surfkit_max_memory() == (uint64_t(16) << 20));
  SurfkitMesh* m = nullptr;
  std::vector<double> p;
  std::vector<uint32_t> o, idx;
  cube(p, o, idx);
  EXPECT(surfkit_mesh_new(p.data(), 8, o.data(), 6, idx.data(), idx.size(), &m) == SURFKIT_OK);
  // 8 levels make 24 · 4^7 = 393 216 quads, about 126 MB at 320 bytes each.
  SurfkitMesh* fine = nullptr;
  EXPECT(surfkit_subdivide(m, 8, nullptr, &fine) == SURFKIT_RESOURCE_LIMIT && fine == nullptr);
  EXPECT(says("393216 quads") && says("memory limit of 16 MiB") && says("6 levels fit"));
  EXPECT(surfkit_subdivide(m, 5, nullptr, &fine) == SURFKIT_OK);
  surfkit_mesh_free(fine);
  // A vertex id is a size claim of the EAT registry (20 bytes per id up to the largest):
  // one near 2³² is refused within the limit instead of aborting on 80 GiB, and registers
  // nothing; small ids still register.
  SurfkitRegistry* g = nullptr;
  EXPECT(surfkit_registry_new(0xFFFFFFFFu, &g) == SURFKIT_OK);
  const uint32_t far[3] = {0xFFFFFFFEu, 1, 2};
  EXPECT(surfkit_registry_add_facet(g, far, 3, 0, nullptr) == SURFKIT_RESOURCE_LIMIT);
  EXPECT(says("vertex id 4294967294") && says("80 GiB") && says("memory limit of 16 MiB"));
  const uint32_t near[3] = {0, 1, 2};
  uint32_t facet = 99;
  EXPECT(surfkit_registry_add_facet(g, near, 3, 1, &facet) == SURFKIT_OK && facet == 0);
  SurfkitEatStatistics stats{};
  EXPECT(surfkit_registry_statistics(g, &stats) == SURFKIT_OK);
  EXPECT(stats.vertices == 3 && stats.edges == 3 && stats.facets == 1);
  surfkit_registry_free(g);
  EXPECT(surfkit_set_max_memory(0) == SURFKIT_OK && surfkit_max_memory() == machine);
  EXPECT(surfkit_subdivide(m, 8, nullptr, &fine) == SURFKIT_OK);
  surfkit_mesh_free(fine);
  surfkit_mesh_free(m);
}

/// The coarse start through the C++ layer: the 64 × 64 grid is the refinement of a 32 × 32
/// one and has 3481 free vertices, a size for the multilevel method. The coarse stage runs
/// when asked (the report says so, in its summary and its JSON), not by default, and not
/// when a vertex is fixed (fixed ids name fine vertices).
static void coarse_start_option() {
  for (int variant = 0; variant < 3; ++variant) {
    Mesh m = grid(64, 0.5f);
    surfkit::FairOptions options;
    options.method = SURFKIT_METHOD_MULTILEVEL;
    options.max_iterations = 1;
    options.coarse_start = variant != 0;
    if (variant == 2) options.fixed.push_back(m.vertex_handle(int(m.n_vertices() / 2)));
    surfkit::FairReport r = surfkit::fair(m, options);
    EXPECT(r.method == SURFKIT_METHOD_MULTILEVEL && r.free_vertices == (variant == 2 ? 3480u : 3481u));
    EXPECT(r.coarse_stage == (variant == 1));
    EXPECT(!r.coarse_start_used || r.coarse_stage);
    EXPECT((r.json.find("\"coarse_start\":{") != std::string::npos) == (variant == 1));
  }
}

/// EatCompanion with degenerate facets (fewer than 3 corners, a repeated vertex): the
/// registry counts them, OpenMesh (whose add_face asserts on them) never sees them, and
/// they are reported as refusals; the mesh keeps only the good facets.
static void companion_degenerate_faces() {
  Mesh m;
  std::vector<Mesh::VertexHandle> v;
  for (int i = 0; i < 4; ++i) v.push_back(m.add_vertex(Mesh::Point(i & 1, i >> 1, 0)));
  surfkit::EatCompanion<Mesh> c(m);
  EXPECT(c.add_face({v[0], v[1], v[2]}).is_valid());
  EXPECT(!c.add_face({v[1]}).is_valid());
  EXPECT(!c.add_face({v[1], v[3]}).is_valid());
  EXPECT(!c.add_face({v[1], v[3], v[1]}).is_valid());
  EXPECT(c.add_face({v[1], v[3], v[2]}).is_valid());
  EXPECT(m.n_faces() == 2);
  const auto& refused = c.refusals();
  EXPECT(refused.size() == 3);
  EXPECT(refused[0].facet == 1 && refused[0].corners.size() == 1);
  EXPECT(refused[0].message == "degenerate: fewer than 3 corners");
  EXPECT(refused[1].facet == 2 && refused[1].message == "degenerate: fewer than 3 corners");
  EXPECT(refused[2].facet == 3 && refused[2].message == "degenerate: a repeated vertex");
  // All five facets count: V = 4, E = 5 (the 1-gon has none, the 2-gon and the repeated
  // vertex's facet run edge 1–3), F = 5.
  auto cp = c.checkpoint(4);
  EXPECT(cp.facets == 5 && cp.vertices == 4 && cp.edges == 5 && cp.verified);
  cp = c.checkpoint(0);
  EXPECT(!cp.verified);
}

/// EatOptions::test_points {{0, χ}} is the whole mesh, as documented; two such points are
/// refused by name; the C door takes null facet counts with one expected value.
static void whole_mesh_test_point() {
  Mesh m = grid(2, 0.f);
  surfkit::EatOptions o;
  o.test_points = {{0, 1}};
  surfkit::EatReport r = surfkit::eat(m, o);
  EXPECT(r.test_points.size() == 1 && r.test_points[0].facets == 4 && r.test_points[0].verified);
  o.test_points = {{0, 2}};
  r = surfkit::eat(m, o);
  EXPECT(r.test_points.size() == 1 && !r.test_points[0].verified && !r.verified);
  o.test_points = {{0, 1}, {0, 1}};
  bool refused = false;
  try {
    surfkit::eat(m, o);
  } catch (const surfkit::Error& e) {
    refused = e.status() == SURFKIT_INVALID_INPUT && std::strstr(e.what(), "whole-mesh") != nullptr;
  }
  EXPECT(refused);
  std::vector<double> p;
  std::vector<uint32_t> off, idx;
  cube(p, off, idx);
  SurfkitMesh* cm = nullptr;
  EXPECT(surfkit_mesh_new(p.data(), 8, off.data(), 6, idx.data(), idx.size(), &cm) == SURFKIT_OK);
  SurfkitEatOptions co{};
  EXPECT(surfkit_eat_options_default(&co) == SURFKIT_OK);
  const int64_t chi = 2;
  co.test_point_facets = nullptr;
  co.test_point_expected = &chi;
  co.test_point_count = 1;
  SurfkitEatReport* report = nullptr;
  EXPECT(surfkit_eat_scan(cm, &co, &report) == SURFKIT_OK);
  SurfkitTestPoint t{};
  EXPECT(surfkit_eat_report_test_point(report, 0, nullptr, &t) == SURFKIT_OK);
  EXPECT(t.facets == 6 && t.verified);
  surfkit_eat_report_free(report);
  const int64_t two[2] = {2, 2};
  co.test_point_expected = two;
  co.test_point_count = 2;
  report = nullptr;
  EXPECT(surfkit_eat_scan(cm, &co, &report) == SURFKIT_INVALID_INPUT && report == nullptr);
  EXPECT(says("test_point_facets is a null pointer"));
  surfkit_mesh_free(cm);
}

int main() {
  EXPECT(surfkit_abi_version() == SURFKIT_ABI_VERSION);
  EXPECT(std::strlen(surfkit_version()) > 0);
  bad_input();
  callbacks();
  float_traits();
  deleted_elements();
  cycles();
  memory_limit();
  coarse_start_option();
  companion_degenerate_faces();
  whole_mesh_test_point();
  failed_calls_clear_outputs();
  mesh_new_checks_its_arrays();
  eat_report_has_the_json_counts();
  fair_updates_the_normals();
  std::cout << "ok: " << checks << " checks" << std::endl;
  return 0;
}
