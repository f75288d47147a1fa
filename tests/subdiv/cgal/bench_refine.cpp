// Reference timings for surfkit's subdivision bench: CGAL's Catmull–Clark and OpenSubdiv
// called directly from C++ (the same work surfkit does through its shim: topology in,
// RefineUniform, PrimvarRefiner in doubles level by level, last level's quads out).
// Usage: bench_refine <in.off> <levels> <repeats> <cgal|opensubdiv>
// Prints "<library> <median seconds>". One library per process: a library timed after
// another would find glibc's heap warmed by the other's large frees (raised mmap and trim
// thresholds) and look up to 2.5x faster than from a fresh process.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/subdivision_method_3.h>

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

typedef CGAL::Simple_cartesian<double> Kernel;
typedef CGAL::Surface_mesh<Kernel::Point_3> Mesh;
using namespace OpenSubdiv;

struct P3 {
  double x[3];
  void Clear() { x[0] = x[1] = x[2] = 0; }
  void AddWithWeight(const P3& p, double w) {
    for (int k = 0; k < 3; ++k) x[k] += w * p.x[k];
  }
};

template <class F>
double median_seconds(int repeats, F&& f) {
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    auto a = std::chrono::steady_clock::now();
    f();
    auto b = std::chrono::steady_clock::now();
    t.push_back(std::chrono::duration<double>(b - a).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

int main(int argc, char** argv) {
  if (argc != 5) return 2;
  const int levels = std::atoi(argv[2]), repeats = std::atoi(argv[3]);
  const std::string which = argv[4];
  if (which != "cgal" && which != "opensubdiv") return 2;
  Mesh input;
  {
    std::ifstream in(argv[1]);
    if (!(in >> input)) return 1;
  }
  // The same mesh as flat arrays for OpenSubdiv.
  std::vector<P3> positions;
  std::vector<int> counts, indices;
  for (auto v : input.vertices()) {
    const auto& p = input.point(v);
    positions.push_back(P3{{p.x(), p.y(), p.z()}});
  }
  for (auto f : input.faces()) {
    counts.push_back(input.degree(f));
    for (auto v : CGAL::vertices_around_face(input.halfedge(f), input)) indices.push_back(v);
  }

  if (which == "opensubdiv") {
    double osd = median_seconds(repeats, [&] {
      Far::TopologyDescriptor desc;
      desc.numVertices = static_cast<int>(positions.size());
      desc.numFaces = static_cast<int>(counts.size());
      desc.numVertsPerFace = counts.data();
      desc.vertIndicesPerFace = indices.data();
      Sdc::Options sdc;
      sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
      typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;
      Far::TopologyRefiner* r = Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc));
      r->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
      Far::PrimvarRefinerReal<double> primvar(*r);
      std::vector<P3> src = positions;
      for (int l = 1; l <= levels; ++l) {
        std::vector<P3> dst(r->GetLevel(l).GetNumVertices());
        primvar.Interpolate(l, src, dst);
        src.swap(dst);
      }
      const Far::TopologyLevel& last = r->GetLevel(levels);
      std::vector<int> quads;
      quads.reserve(4 * last.GetNumFaces());
      for (int f = 0; f < last.GetNumFaces(); ++f) {
        Far::ConstIndexArray fv = last.GetFaceVertices(f);
        for (int k = 0; k < fv.size(); ++k) quads.push_back(fv[k]);
      }
      delete r;
    });
    std::cout << "opensubdiv " << osd << "\n";
    return 0;
  }
  double cgal = median_seconds(repeats, [&] {
    Mesh m = input;
    CGAL::Subdivision_method_3::CatmullClark_subdivision(
        m, CGAL::parameters::number_of_iterations(levels));
    if (m.number_of_faces() == 0) std::abort();
  });
  // Copying the input mesh is not part of CGAL's refinement: time it alone and subtract.
  double copy = median_seconds(repeats, [&] {
    Mesh m = input;
    if (m.number_of_faces() == 0) std::abort();
  });

  std::cout << "cgal " << std::max(0.0, cgal - copy) << "\n";
  return 0;
}
