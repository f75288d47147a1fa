// The Euler Accompanying Test as a modelling program uses it (Liu et al. 2020 §3–4): the
// model is built facet by facet in an OpenMesh mesh; surfkit::EatCompanion registers every
// facet (also those OpenMesh refuses) and, at the end of each drawing stage, a test point
// compares χ with what the designer meant to have. The first failing test point stops the
// drawing and lists the facets drawn since the last verified point: where to look.
//
//   modeller_companion SCRIPT
//
// SCRIPT is the drawing: lines `v x y z` (a vertex), `f i j k …` (a facet, 0-based vertex
// ids) and `check CHI` (a test point: χ so far should be CHI). Exit status 0 when every test
// point is verified, 3 at the first failing one, 1 on an error.
#include <surfkit/openmesh.hh>

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using Mesh = OpenMesh::PolyMesh_ArrayKernelT<>;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: modeller_companion SCRIPT\n";
    return 2;
  }
  std::ifstream script(argv[1]);
  if (!script) {
    std::cerr << "cannot read " << argv[1] << "\n";
    return 1;
  }
  try {
    Mesh mesh;
    surfkit::EatCompanion<Mesh> companion(mesh);
    std::string line;
    size_t line_number = 0, stage = 0;
    while (std::getline(script, line)) {
      ++line_number;
      std::istringstream words(line);
      std::string what;
      words >> what;
      if (what == "v") {
        float x, y, z;
        if (!(words >> x >> y >> z)) throw std::runtime_error("line " + std::to_string(line_number) + ": bad vertex");
        mesh.add_vertex(Mesh::Point(x, y, z));
      } else if (what == "f") {
        std::vector<Mesh::VertexHandle> corners;
        for (int id; words >> id;) corners.push_back(mesh.vertex_handle(id));
        companion.add_face(corners);
      } else if (what == "check") {
        long long expected;
        if (!(words >> expected)) throw std::runtime_error("line " + std::to_string(line_number) + ": bad check");
        auto c = companion.checkpoint(expected);
        ++stage;
        std::cout << "test point " << stage << ": V " << c.vertices << " E " << c.edges << " F " << c.facets
                  << " chi " << c.euler_characteristic << " expected " << expected
                  << (c.verified ? " verified" : " FAILED") << "\n";
        if (!c.verified) {
          std::cout << "suspects";
          for (const auto& s : c.suspects) std::cout << ' ' << s.first;
          std::cout << "\n";
          std::cout << "refused";
          for (const auto& r : companion.refusals()) std::cout << ' ' << r.facet;
          std::cout << "\n";
          return 3;
        }
      }
    }
    std::cout << "refused";
    for (const auto& r : companion.refusals()) std::cout << ' ' << r.facet;
    std::cout << "\n";
  } catch (const surfkit::Error& e) {
    std::cerr << "surfkit error " << e.status() << ": " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
