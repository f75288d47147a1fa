// CGAL's Catmull–Clark (Subdivision_method_3::CatmullClark_subdivision on a Surface_mesh):
// the independent reference surfkit's subdivision tests compare against.
// Usage: catmull_clark <in.off> <levels> <out.off>   (writes 17 significant digits)
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/subdivision_method_3.h>

#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>

typedef CGAL::Simple_cartesian<double> Kernel;
typedef CGAL::Surface_mesh<Kernel::Point_3> Mesh;

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: catmull_clark <in.off> <levels> <out.off>\n";
    return 2;
  }
  Mesh mesh;
  std::ifstream in(argv[1]);
  if (!in || !(in >> mesh) || mesh.is_empty()) {
    std::cerr << "cannot read " << argv[1] << " as a Surface_mesh\n";
    return 1;
  }
  const int levels = std::atoi(argv[2]);
  CGAL::Subdivision_method_3::CatmullClark_subdivision(
      mesh, CGAL::parameters::number_of_iterations(levels));
  std::ofstream out(argv[3]);
  out << std::setprecision(17);
  out << "OFF\n" << mesh.number_of_vertices() << ' ' << mesh.number_of_faces() << " 0\n";
  std::map<Mesh::Vertex_index, int> id;
  int next = 0;
  for (auto v : mesh.vertices()) {
    id[v] = next++;
    const auto& p = mesh.point(v);
    out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  }
  for (auto f : mesh.faces()) {
    out << mesh.degree(f);
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) out << ' ' << id[v];
    out << '\n';
  }
  return out ? 0 : 1;
}
