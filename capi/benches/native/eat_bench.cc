// Times the EAT through the C++ layer on an OpenMesh mesh (bench eat_openmesh):
//   eat_bench MESH REPEATS  ->  one JSON line of median seconds over REPEATS runs:
//   "eat" surfkit::eat(mesh) whole (flattening, the scan, handles mapped back), "flatten"
//   the flattening into surfkit's arrays alone, "scan" surfkit_eat_scan on an already
//   flattened mesh (what the C++ layer adds nothing to), and "read" OpenMesh's read_mesh.
#include <surfkit/openmesh.hh>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <vector>

using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;

template <class F>
static double median_seconds(int repeats, F f) {
  f();
  std::vector<double> t;
  for (int i = 0; i < repeats; ++i) {
    auto t0 = std::chrono::steady_clock::now();
    f();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

int main(int argc, char** argv) {
  if (argc != 3) return 2;
  const int repeats = std::atoi(argv[2]);
  Mesh mesh;
  auto t0 = std::chrono::steady_clock::now();
  if (!OpenMesh::IO::read_mesh(mesh, argv[1])) {
    std::cerr << "cannot read " << argv[1] << "\n";
    return 1;
  }
  double read = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  size_t faces = 0, flaws = 0;
  double eat = median_seconds(repeats, [&] {
    auto r = surfkit::eat(mesh);
    faces = r.faces;
    flaws = r.flaws.size();
  });
  double flatten = median_seconds(repeats, [&] { surfkit::detail::Flattened<Mesh> flat(mesh); flat.make(); });
  surfkit::detail::Flattened<Mesh> flat(mesh);
  auto soup = flat.make();
  SurfkitEatOptions options;
  surfkit_eat_options_default(&options);
  double scan = median_seconds(repeats, [&] {
    SurfkitEatReport* r = nullptr;
    surfkit::detail::check(surfkit_eat_scan(soup.get(), &options, &r));
    surfkit_eat_report_free(r);
  });
  std::cout << "{\"read\": " << read << ", \"eat\": " << eat << ", \"flatten\": " << flatten << ", \"scan\": " << scan
            << ", \"faces\": " << faces << ", \"flaws\": " << flaws << "}" << std::endl;
  return 0;
}
