// Implementation of the OpenMesh bridge (see bridge.h).
#include "surfkit/cpp/openmesh/bridge.h"
#include <algorithm>

#include <iostream>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "surfkit/src/ffi/openmesh.rs.h"

namespace surfkit {
namespace om {

namespace {

constexpr uint32_t NONE = 0xffffffffu;

// Face status codes; keep in step with `FaceStatus` in src/ffi/openmesh.rs.
constexpr uint8_t ADDED = 0;
constexpr uint8_t COMPLEX_EDGE = 1;
constexpr uint8_t COMPLEX_VERTEX = 2;
constexpr uint8_t RELINK_FAILED = 3;
constexpr uint8_t DEGENERATE = 4;
constexpr uint8_t OTHER = 5;

// OpenMesh writes its complaints to the global omerr() stream, which goes to std::cerr.
// omerr()'s stream buffer is replaced once per process by a router that appends to the
// calling thread's capture string while a CaptureOmerr is alive there, and forwards to
// std::cerr otherwise. (Replacing the buffer, not disconnecting std::cerr from OpenMesh's
// multiplexer and connecting a target: mostream::disconnect never deletes the target it
// made in connect, a leak LeakSanitizer reports.) Calls into OpenMesh are serialized by a
// lock, since omerr() is global.
std::mutex omerr_lock;
thread_local std::string* omerr_capture = nullptr;

class OmerrRouter : public std::streambuf {
 protected:
  int_type overflow(int_type c) override {
    if (c != traits_type::eof()) {
      char ch = traits_type::to_char_type(c);
      xsputn(&ch, 1);
    }
    return traits_type::not_eof(c);
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (omerr_capture != nullptr)
      omerr_capture->append(s, static_cast<size_t>(n));
    else
      std::cerr.write(s, n);
    return n;
  }
};

void install_omerr_router() {
  static const bool installed = [] {
    static OmerrRouter router;
    omerr().flush();
    omerr().rdbuf(&router);
    return true;
  }();
  (void)installed;
}

class CaptureOmerr {
 public:
  CaptureOmerr() : guard_(omerr_lock) {
    install_omerr_router();
    omerr().flush();
    previous_ = omerr_capture;
    omerr_capture = &captured_;
  }
  ~CaptureOmerr() {
    omerr().flush();
    omerr_capture = previous_;
  }
  /// What OpenMesh said since the last call.
  std::string take() {
    omerr().flush();
    std::string s;
    s.swap(captured_);
    return s;
  }

 private:
  std::lock_guard<std::mutex> guard_;
  std::string captured_;
  std::string* previous_ = nullptr;
};

uint8_t classify(const std::string& message) {
  if (message.find("complex edge") != std::string::npos) return COMPLEX_EDGE;
  if (message.find("complex vertex") != std::string::npos) return COMPLEX_VERTEX;
  if (message.find("re-linking") != std::string::npos) return RELINK_FAILED;
  return OTHER;
}

// Whether the n corners at `corners` repeat a vertex: small facets by pairs, large ones
// sorted in `scratch` (a facet may have a million corners).
bool has_repeated_corner(const uint32_t* corners, size_t n, std::vector<uint32_t>& scratch) {
  if (n <= 32) {
    for (size_t i = 0; i < n; ++i)
      for (size_t j = i + 1; j < n; ++j)
        if (corners[i] == corners[j]) return true;
    return false;
  }
  scratch.assign(corners, corners + n);
  std::sort(scratch.begin(), scratch.end());
  return std::adjacent_find(scratch.begin(), scratch.end()) != scratch.end();
}

// Adds one face; returns its status and appends OpenMesh's message (if any) to `said`.
uint8_t add_one(HalfEdgeMesh& m, const uint32_t* corners, size_t n, uint32_t input_id,
                CaptureOmerr& capture, std::string& said) {
  // The mesh's reused buffer: a fresh vector per face was 4M allocations on 4M faces.
  std::vector<PolyMesh::VertexHandle>& vs = m.corner_buffer;
  vs.resize(n);
  for (size_t k = 0; k < n; ++k) {
    if (corners[k] >= m.mesh.n_vertices())
      throw std::out_of_range("face " + std::to_string(input_id) + " refers to vertex " +
                              std::to_string(corners[k]) + " but the mesh has " +
                              std::to_string(m.mesh.n_vertices()) + " vertices");
    vs[k] = PolyMesh::VertexHandle(static_cast<int>(corners[k]));
  }
  std::vector<uint32_t> scratch;  // allocated only for a face of over 32 corners
  if (n < 3 || has_repeated_corner(corners, n, scratch)) return DEGENERATE;
  auto fh = m.mesh.add_face(vs);
  if (fh.is_valid()) {
    // OpenMesh speaks only when it refuses a face: no flush of omerr() per added face.
    m.input_face.push_back(input_id);
    m.first_corner.push_back(corners[0]);
    return ADDED;
  }
  std::string msg = capture.take();
  if (msg.empty()) msg = "PolyMeshT::add_face: refused without a message\n";
  said += "face " + std::to_string(input_id) + ": " + msg;
  return classify(msg);
}

// Builds the half-edge structure of an oriented 2-manifold directly: every directed edge
// paired with its reverse through the edges leaving each vertex, then OpenMesh's edges,
// faces, next links and outgoing half-edges set with the kernel's own setters — what
// add_face makes of such a mesh in any face order, without its per-face searches (2/3 of
// the scan's time on a 1M-triangle mesh). Returns false, with the mesh untouched, where the
// facets are not one (a repeated or missing corner, an edge used twice in one direction or
// by more than two facets, a vertex whose facets form more than one fan): add_face then
// builds what it can and reports what it refuses.
bool build_manifold(HalfEdgeMesh& m, rust::Slice<const uint32_t> offsets,
                    rust::Slice<const uint32_t> indices) {
  constexpr uint32_t NONE = UINT32_MAX;
  const size_t nv = m.mesh.n_vertices();
  const size_t nf = offsets.size() - 1;
  const size_t nh = indices.size();
  // Raw pointers: rust::Slice's operator[] is a call into Rust per element.
  const uint32_t* const corner = indices.data();
  const uint32_t* const offset = offsets.data();
  if (nh >= NONE || nv >= NONE) return false;
  // Corner h's successor and predecessor in its face. Meshes of one face size (all
  // triangles, all quads) compute them; others keep two arrays of one entry per corner.
  uint32_t arity = nf > 0 ? offset[1] - offset[0] : 0;
  for (size_t f = 0; f < nf && arity != 0; ++f)
    if (offset[f + 1] - offset[f] != arity || offset[f] != f * arity) arity = 0;
  std::vector<uint32_t> next_of, prev_of;
  if (arity == 0) {
    next_of.resize(nh);
    prev_of.resize(nh);
  }
  std::vector<uint32_t> sorted_corners;
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t a = offset[f], b = offset[f + 1];
    if (b < a || b - a < 3) return false;
    // A repeated corner (f 1 2 3 1) is a degenerate facet: add_face refuses it. Built
    // here it would be a self-loop half-edge or a facet on both sides of its own edges,
    // which OpenMesh's walks do not survive.
    if (has_repeated_corner(corner + a, b - a, sorted_corners)) return false;
    for (uint32_t h = a; h < b; ++h) {
      if (corner[h] >= nv) return false;
      if (arity == 0) {
        next_of[h] = h + 1 < b ? h + 1 : a;
        prev_of[h] = h > a ? h - 1 : b - 1;
      }
    }
  }
  auto next = [&](uint32_t h) {
    return arity != 0 ? (h % arity + 1 == arity ? h + 1 - arity : h + 1) : next_of[h];
  };
  auto prev = [&](uint32_t h) {
    return arity != 0 ? (h % arity == 0 ? h + arity - 1 : h - 1) : prev_of[h];
  };
  auto from = [&](uint32_t h) { return corner[h]; };
  auto to = [&](uint32_t h) { return corner[next(h)]; };
  // The half-edges leaving each vertex, each vertex's run sorted by the vertex they reach
  // (so a repeated direction is two neighbours and a twin one binary search, whatever the
  // valence: a hub of a million triangles costs n log n, not n²).
  std::vector<uint32_t> out_start(nv + 1, 0);
  for (size_t h = 0; h < nh; ++h) ++out_start[corner[h] + 1];
  for (size_t v = 0; v < nv; ++v) out_start[v + 1] += out_start[v];
  std::vector<uint64_t> leaving(nh);  // (reached vertex << 32) | half-edge
  {
    std::vector<uint32_t> fill(out_start.begin(), out_start.end() - 1);
    for (size_t h = 0; h < nh; ++h)
      leaving[fill[corner[h]]++] = (static_cast<uint64_t>(to(static_cast<uint32_t>(h))) << 32) | h;
  }
  for (size_t v = 0; v < nv; ++v)
    if (out_start[v + 1] - out_start[v] > 1)
      std::sort(leaving.begin() + out_start[v], leaving.begin() + out_start[v + 1]);
  auto reached = [&](uint32_t i) { return static_cast<uint32_t>(leaving[i] >> 32); };
  auto half = [&](uint32_t i) { return static_cast<uint32_t>(leaving[i]); };
  // Twins; an edge twice in one direction (a repeated facet corner pair, three facets on
  // an edge, or facets oriented against each other) is no oriented manifold.
  std::vector<uint32_t> twin(nh, NONE);
  for (size_t v = 0; v < nv; ++v) {
    for (uint32_t i = out_start[v]; i < out_start[v + 1]; ++i) {
      const uint32_t w = reached(i);
      if (i + 1 < out_start[v + 1] && reached(i + 1) == w) return false;
      const uint64_t key = static_cast<uint64_t>(v) << 32;
      const auto first = leaving.begin() + out_start[w], last = leaving.begin() + out_start[w + 1];
      const auto it = std::lower_bound(first, last, key);
      if (it != last && (*it >> 32) == v) twin[half(i)] = static_cast<uint32_t>(*it);
    }
  }
  // One fan per vertex: turning from one leaving half-edge to the next (twin of the
  // previous one, and back the other way from a boundary) must meet them all.
  for (size_t v = 0; v < nv; ++v) {
    const uint32_t count = out_start[v + 1] - out_start[v];
    if (count == 0) continue;
    const uint32_t start = half(out_start[v]);
    uint32_t seen = 1, h = start;
    bool closed = false;
    while (true) {
      const uint32_t t = twin[prev(h)];
      if (t == NONE) break;
      if (t == start) {
        closed = true;
        break;
      }
      if (++seen > count) return false;
      h = t;
    }
    if (!closed) {
      h = start;
      while (twin[h] != NONE) {
        h = next(twin[h]);
        if (++seen > count) return false;
      }
    }
    if (seen != count) return false;
  }
  // The structure: an edge's half-edge 0 runs from the start given to new_edge to its end.
  // Storage sized once (new_edge and new_face resize every property per element).
  PolyMesh& mesh = m.mesh;
  size_t ne = 0;
  for (uint32_t h = 0; h < nh; ++h) ne += twin[h] == NONE || twin[h] > h;
  mesh.resize(nv, ne, nf);
  std::vector<PolyMesh::HalfedgeHandle> om(nh);
  std::vector<PolyMesh::HalfedgeHandle> boundary_out(nv);
  std::vector<PolyMesh::HalfedgeHandle> boundary;
  int e = 0;
  for (uint32_t h = 0; h < nh; ++h) {
    if (twin[h] != NONE && twin[h] < h) continue;
    // Half-edge 0 of edge e runs from(h) -> to(h), as new_edge would set it.
    const PolyMesh::EdgeHandle eh(e++);
    const auto h0 = mesh.halfedge_handle(eh, 0), h1 = mesh.halfedge_handle(eh, 1);
    mesh.set_vertex_handle(h0, PolyMesh::VertexHandle(static_cast<int>(to(h))));
    mesh.set_vertex_handle(h1, PolyMesh::VertexHandle(static_cast<int>(from(h))));
    om[h] = h0;
    if (twin[h] != NONE) {
      om[twin[h]] = h1;
    } else {
      boundary_out[to(h)] = h1;  // to(h) -> from(h), no face
      boundary.push_back(h1);
    }
  }
  for (size_t f = 0; f < nf; ++f) {
    const PolyMesh::FaceHandle fh(static_cast<int>(f));
    mesh.set_halfedge_handle(fh, om[offset[f]]);
    for (uint32_t h = offset[f]; h < offset[f + 1]; ++h) {
      mesh.set_face_handle(om[h], fh);
      mesh.set_next_halfedge_handle(om[h], om[next(h)]);
    }
  }
  for (const auto b : boundary)
    mesh.set_next_halfedge_handle(b, boundary_out[mesh.to_vertex_handle(b).idx()]);
  for (size_t v = 0; v < nv; ++v) {
    const PolyMesh::VertexHandle vh(static_cast<int>(v));
    if (boundary_out[v].is_valid())
      mesh.set_halfedge_handle(vh, boundary_out[v]);
    else if (out_start[v + 1] > out_start[v])
      mesh.set_halfedge_handle(vh, om[half(out_start[v])]);
  }
  m.input_face.resize(nf);
  m.first_corner.resize(nf);
  for (size_t f = 0; f < nf; ++f) {
    m.input_face[f] = static_cast<uint32_t>(f);
    m.first_corner[f] = corner[offset[f]];
  }
  return true;
}

}  // namespace

std::unique_ptr<HalfEdgeMesh> build(rust::Slice<const double> positions,
                                    rust::Slice<const uint32_t> offsets,
                                    rust::Slice<const uint32_t> indices, BuildLog& log) {
  if (positions.size() % 3 != 0) throw std::invalid_argument("positions must be x,y,z triples");
  if (offsets.empty() || offsets[0] != 0 || offsets[offsets.size() - 1] != indices.size())
    throw std::invalid_argument("face offsets must run from 0 to the number of indices");
  auto m = std::make_unique<HalfEdgeMesh>();
  const size_t nv = positions.size() / 3;
  const size_t nf = offsets.size() - 1;
  m->mesh.reserve(nv, indices.size(), nf);
  for (size_t v = 0; v < nv; ++v)
    m->mesh.add_vertex(PolyMesh::Point(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]));
  m->input_face.reserve(nf);
  log.face_status.reserve(nf);
  if (build_manifold(*m, offsets, indices)) {
    log.all_added = true;  // face_status stays empty: a push_back per face crosses into Rust
    return m;
  }
  std::string said;
  CaptureOmerr capture;
  for (size_t f = 0; f < nf; ++f) {
    if (offsets[f + 1] < offsets[f]) throw std::invalid_argument("face offsets decrease at face " + std::to_string(f));
    log.face_status.push_back(add_one(*m, indices.data() + offsets[f], offsets[f + 1] - offsets[f],
                                      static_cast<uint32_t>(f), capture, said));
  }
  log.messages = said;
  return m;
}

uint8_t HalfEdgeMesh::add_face(rust::Slice<const uint32_t> corners, uint32_t input_id,
                               rust::String& message) {
  CaptureOmerr capture;
  std::string said;
  uint8_t status = add_one(*this, corners.data(), corners.size(), input_id, capture, said);
  message = said;
  return status;
}

void HalfEdgeMesh::add_faces(rust::Slice<const uint32_t> offsets, rust::Slice<const uint32_t> indices,
                             uint32_t first_input_id, rust::Vec<uint8_t>& status,
                             rust::String& messages) {
  if (offsets.empty() || offsets[0] != 0 || offsets[offsets.size() - 1] != indices.size())
    throw std::invalid_argument("face offsets must run from 0 to the number of indices");
  CaptureOmerr capture;
  std::string said;
  for (size_t f = 0; f + 1 < offsets.size(); ++f) {
    if (offsets[f + 1] < offsets[f]) throw std::invalid_argument("face offsets decrease at face " + std::to_string(f));
    status.push_back(add_one(*this, indices.data() + offsets[f], offsets[f + 1] - offsets[f],
                             first_input_id + static_cast<uint32_t>(f), capture, said));
  }
  messages = said;
}

void HalfEdgeMesh::add_vertices(rust::Slice<const double> positions) {
  if (positions.size() % 3 != 0) throw std::invalid_argument("positions must be x,y,z triples");
  for (size_t v = 0; v < positions.size() / 3; ++v)
    mesh.add_vertex(PolyMesh::Point(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]));
}

size_t HalfEdgeMesh::n_vertices() const { return mesh.n_vertices(); }
size_t HalfEdgeMesh::n_edges() const { return mesh.n_edges(); }
size_t HalfEdgeMesh::n_faces() const { return mesh.n_faces(); }

void HalfEdgeMesh::face_ids(rust::Vec<uint32_t>& out) const {
  out.clear();
  out.reserve(input_face.size());
  for (auto f : input_face) out.push_back(f);
}

void HalfEdgeMesh::boundary_loops(rust::Vec<uint32_t>& offsets, rust::Vec<uint32_t>& vertices) const {
  // Walk boundary half-edges; at each vertex continue with the next boundary half-edge of
  // the same fan of faces (rotating through prev/opposite, which never leaves the fan), so
  // that at a pinch vertex each fan's boundary closes its own loop. OpenMesh's own
  // next_halfedge link at such a vertex may jump between fans.
  std::vector<char> seen(mesh.n_halfedges(), 0);
  offsets.clear();
  vertices.clear();
  offsets.push_back(0);
  for (auto h : mesh.halfedges()) {
    if (!h.is_boundary() || seen[h.idx()]) continue;
    auto cur = h;
    while (!seen[cur.idx()]) {
      seen[cur.idx()] = 1;
      vertices.push_back(static_cast<uint32_t>(cur.from().idx()));
      // Find the boundary half-edge leaving cur.to() in the same fan.
      auto g = cur.opp();
      size_t guard = 0;
      while (!g.is_boundary()) {
        g = g.prev().opp();
        if (++guard > mesh.n_halfedges()) throw std::runtime_error("boundary walk did not close");
      }
      cur = g;
    }
    offsets.push_back(static_cast<uint32_t>(vertices.size()));
  }
}

void HalfEdgeMesh::vertex_valences(rust::Vec<uint32_t>& out) const {
  out.clear();
  out.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) out.push_back(static_cast<uint32_t>(mesh.valence(v)));
}

void HalfEdgeMesh::edges(rust::Vec<uint32_t>& vertices, rust::Vec<uint32_t>& faces) const {
  vertices.clear();
  faces.clear();
  vertices.reserve(2 * mesh.n_edges());
  faces.reserve(2 * mesh.n_edges());
  for (auto e : mesh.edges()) {
    for (int side = 0; side < 2; ++side) {
      auto h = e.halfedge(side);
      vertices.push_back(static_cast<uint32_t>(h.from().idx()));
      faces.push_back(h.face().is_valid() ? input_face[h.face().idx()] : NONE);
    }
  }
}

void HalfEdgeMesh::face_neighbours(rust::Vec<uint32_t>& offsets, rust::Vec<uint32_t>& neighbours) const {
  offsets.clear();
  neighbours.clear();
  offsets.push_back(0);
  for (auto f : mesh.faces()) {
    auto start = f.halfedge();
    while (static_cast<uint32_t>(start.from().idx()) != first_corner[f.idx()]) start = start.next();
    auto h = start;
    do {
      auto o = h.opp().face();
      neighbours.push_back(o.is_valid() ? input_face[o.idx()] : NONE);
      h = h.next();
    } while (h != start);
    offsets.push_back(static_cast<uint32_t>(neighbours.size()));
  }
}

uint32_t HalfEdgeMesh::connected_components(rust::Vec<uint32_t>& face_component) const {
  face_component.clear();
  std::vector<uint32_t> comp(mesh.n_faces(), NONE);
  uint32_t count = 0;
  std::vector<OpenMesh::SmartFaceHandle> stack;
  for (auto seed : mesh.faces()) {
    if (comp[seed.idx()] != NONE) continue;
    comp[seed.idx()] = count;
    stack.push_back(seed);
    while (!stack.empty()) {
      auto f = stack.back();
      stack.pop_back();
      for (auto g : f.faces())
        if (comp[g.idx()] == NONE) {
          comp[g.idx()] = count;
          stack.push_back(g);
        }
    }
    ++count;
  }
  for (auto c : comp) face_component.push_back(c);
  return count;
}

void HalfEdgeMesh::positions(rust::Vec<double>& out) const {
  out.clear();
  out.reserve(3 * mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    out.push_back(p[0]);
    out.push_back(p[1]);
    out.push_back(p[2]);
  }
}

void HalfEdgeMesh::set_positions(rust::Slice<const double> positions) {
  if (positions.size() != 3 * mesh.n_vertices())
    throw std::invalid_argument("expected " + std::to_string(3 * mesh.n_vertices()) +
                                " coordinates, got " + std::to_string(positions.size()));
  for (auto v : mesh.vertices())
    mesh.set_point(v, PolyMesh::Point(positions[3 * v.idx()], positions[3 * v.idx() + 1],
                                      positions[3 * v.idx() + 2]));
}

void HalfEdgeMesh::write_with_openmesh(rust::Str path) const {
  CaptureOmerr capture;
  std::string p(path.data(), path.size());
  OpenMesh::IO::Options opt;
  if (!OpenMesh::IO::write_mesh(mesh, p, opt)) {
    std::string msg = capture.take();
    throw std::runtime_error("OpenMesh could not write " + p + (msg.empty() ? "" : ": " + msg));
  }
}

std::unique_ptr<HalfEdgeMesh> read_with_openmesh(rust::Str path) {
  CaptureOmerr capture;
  auto m = std::make_unique<HalfEdgeMesh>();
  std::string p(path.data(), path.size());
  if (!OpenMesh::IO::read_mesh(m->mesh, p)) {
    std::string msg = capture.take();
    throw std::runtime_error("OpenMesh could not read " + p + (msg.empty() ? "" : ": " + msg));
  }
  m->input_face.resize(m->mesh.n_faces());
  m->first_corner.resize(m->mesh.n_faces());
  for (auto f : m->mesh.faces()) {
    m->input_face[f.idx()] = static_cast<uint32_t>(f.idx());
    m->first_corner[f.idx()] = static_cast<uint32_t>(f.halfedge().from().idx());
  }
  return m;
}

rust::String openmesh_version() {
#ifdef OM_VERSION
  int v = OM_VERSION;
  return std::to_string((v >> 16) & 0xff) + "." + std::to_string((v >> 8) & 0xff);
#else
  return "unknown";
#endif
}

}  // namespace om
}  // namespace surfkit
