// surfkit's bridge to OpenMesh: a PolyMesh with double-precision points, built from a
// polygon soup in one batched call, queried through flat arrays. Called from Rust through
// cxx (src/ffi/openmesh.rs); every function that can fail throws std::exception, which
// cxx turns into a Rust Err — nothing aborts across the boundary.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "rust/cxx.h"

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

namespace surfkit {
namespace om {

struct BuildLog;

/// OpenMesh traits: double-precision points (surfkit never loses input precision).
struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};

typedef OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits> PolyMesh;

/// An OpenMesh PolyMesh plus the map from OpenMesh's face handles to input face ids
/// (OpenMesh numbers only the faces it accepts).
class HalfEdgeMesh {
 public:
  PolyMesh mesh;
  std::vector<uint32_t> input_face;
  /// First corner of each accepted face as given, so that per-corner answers follow the
  /// input's corner order (OpenMesh's face half-edge may start at another corner).
  std::vector<uint32_t> first_corner;
  // The corners of the face being added (reused: one allocation, not one per face).
  std::vector<PolyMesh::VertexHandle> corner_buffer;

  size_t n_vertices() const;
  size_t n_edges() const;
  size_t n_faces() const;
  void face_ids(rust::Vec<uint32_t>& out) const;
  void boundary_loops(rust::Vec<uint32_t>& offsets, rust::Vec<uint32_t>& vertices) const;
  void vertex_valences(rust::Vec<uint32_t>& out) const;
  void edges(rust::Vec<uint32_t>& vertices, rust::Vec<uint32_t>& faces) const;
  void face_neighbours(rust::Vec<uint32_t>& offsets, rust::Vec<uint32_t>& neighbours) const;
  uint32_t connected_components(rust::Vec<uint32_t>& face_component) const;
  void positions(rust::Vec<double>& out) const;
  void set_positions(rust::Slice<const double> positions);
  uint8_t add_face(rust::Slice<const uint32_t> corners, uint32_t input_id, rust::String& message);
  void add_faces(rust::Slice<const uint32_t> offsets, rust::Slice<const uint32_t> indices,
                 uint32_t first_input_id, rust::Vec<uint8_t>& status, rust::String& messages);
  void add_vertices(rust::Slice<const double> positions);
  void write_with_openmesh(rust::Str path) const;
};

std::unique_ptr<HalfEdgeMesh> build(rust::Slice<const double> positions,
                                    rust::Slice<const uint32_t> offsets,
                                    rust::Slice<const uint32_t> indices, BuildLog& log);

std::unique_ptr<HalfEdgeMesh> read_with_openmesh(rust::Str path);

rust::String openmesh_version();

}  // namespace om
}  // namespace surfkit
