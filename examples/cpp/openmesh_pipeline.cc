// An OpenMesh pipeline with surfkit in-process: read a mesh with OpenMesh, check it with the
// Euler Accompanying Test, refine it with Catmull–Clark, fair a tube junction with
// Kiciak's optimizer (the optimized points written back into the OpenMesh mesh) and write
// the results with OpenMesh.
//
//   openmesh_pipeline MESH TUBES OUT_DIR
//
// Prints the EAT's counts and flaws (handles as indices), the fairing's figures, and writes
// OUT_DIR/held.obj (the mesh as OpenMesh holds it), OUT_DIR/subdivided.obj (2 levels),
// OUT_DIR/faired.obj. OpenMesh's OBJ writer goes through float, so the exact double
// coordinates are also written, one vertex a line, to held.xyz, subdivided.xyz and
// faired.xyz (what the tests compare bit for bit). Exit status 1 on any error.
#include <surfkit/openmesh.hh>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <fstream>
#include <iostream>
#include <string>

struct DoubleTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using Mesh = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;

static void write(const Mesh& mesh, const std::string& path) {
  if (!OpenMesh::IO::write_mesh(mesh, path, OpenMesh::IO::Options::Default, 17))
    throw std::runtime_error("cannot write " + path);
}

static void write_xyz(const Mesh& mesh, const std::string& path) {
  std::ofstream out(path);
  out.precision(17);
  for (auto vh : mesh.vertices()) {
    const auto& p = mesh.point(vh);
    out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  }
  if (!out) throw std::runtime_error("cannot write " + path);
}

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: openmesh_pipeline MESH TUBES OUT_DIR\n";
    return 2;
  }
  const std::string out = argv[3];
  try {
    Mesh mesh;
    if (!OpenMesh::IO::read_mesh(mesh, argv[1])) throw std::runtime_error(std::string("cannot read ") + argv[1]);
    write(mesh, out + "/held.obj");
    write_xyz(mesh, out + "/held.xyz");

    surfkit::EatReport r = surfkit::eat(mesh);
    std::cout << "eat V " << r.vertices << " E " << r.edges << " F " << r.faces << " chi "
              << r.euler_characteristic << " loops " << r.boundary_loops << " components " << r.components
              << " genus " << r.genus << " flaws " << r.flaws.size() << "\n";
    for (const surfkit::Flaw& f : r.flaws) {
      std::cout << "flaw " << f.kind << " v";
      for (auto vh : f.vertices) std::cout << ' ' << vh.idx();
      std::cout << " f";
      for (auto fh : f.faces) std::cout << ' ' << fh.idx();
      std::cout << " fix " << (!f.fix_verified ? "unchecked" : *f.fix_verified ? "verified" : "not verified")
                << "\n";
    }

    Mesh fine = surfkit::subdivide(mesh, 2);
    write(fine, out + "/subdivided.obj");
    write_xyz(fine, out + "/subdivided.xyz");
    std::cout << "subdivided V " << fine.n_vertices() << " F " << fine.n_faces() << "\n";

    Mesh tubes;
    if (!OpenMesh::IO::read_mesh(tubes, argv[2])) throw std::runtime_error(std::string("cannot read ") + argv[2]);
    surfkit::FairOptions options;
    options.progress = [](const surfkit::FairIteration& it) {
      std::cerr << "  iteration " << it.iteration << ": F " << it.f << ", |g|/|g0| "
                << it.gradient_norm / it.initial_gradient_norm << "\n";
      return true;
    };
    surfkit::FairReport q = surfkit::fair(tubes, options);
    write(tubes, out + "/faired.obj");
    write_xyz(tubes, out + "/faired.xyz");
    std::cout.precision(17);
    std::cout << "fair converged " << q.converged << " iterations " << q.iterations << " S " << q.s_before
              << " -> " << q.s_after << " F " << q.f_before << " -> " << q.f_after << "\n";
  } catch (const surfkit::Error& e) {
    std::cerr << "surfkit error " << e.status() << ": " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
