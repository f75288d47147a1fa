// The spline door from C++ (run by capi/tests/cpp_door.rs): fits the data of a CSV file
// (u,v,x,y,z lines) with surfkit::fit and prints σ at an 11 × 11 grid of the data's
// parameter rectangle, 17 significant digits, one point a line.
//   fit_check DATA.csv SPACE CELLS HOLE SHAPE
// SPACE 0 biquadratic, 1 bicubic, 2 BFS C¹; HOLE 0 none, 1 cells without data;
// SHAPE 1: z ≥ 0 imposed in the hole (2024), with a 2 × 2 lattice per hole cell.
#include <surfkit/openmesh.hh>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 6) return 2;
  std::ifstream in(argv[1]);
  std::vector<std::array<double, 2>> uv;
  std::vector<std::array<double, 3>> xyz;
  std::string line;
  while (std::getline(in, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream w(line);
    double u, v, x, y, z;
    if (w >> u >> v >> x >> y >> z) {
      uv.push_back({u, v});
      xyz.push_back({x, y, z});
    }
  }
  surfkit::FitOptions options;
  options.space = std::atoi(argv[2]);
  options.cells_u = options.cells_v = static_cast<unsigned>(std::atoi(argv[3]));
  options.hole = std::atoi(argv[4]);
  if (std::atoi(argv[5]) == 1) {
    options.shape_component = 2;
    options.shape_value = 1;
    options.shape_lattice = 2;
  }
  try {
    surfkit::Spline s = surfkit::fit(uv, xyz, options);
    double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
    for (const auto& p : uv) {
      u0 = std::min(u0, p[0]);
      u1 = std::max(u1, p[0]);
      v0 = std::min(v0, p[1]);
      v1 = std::max(v1, p[1]);
    }
    std::cout.precision(17);
    for (int j = 0; j <= 10; ++j)
      for (int i = 0; i <= 10; ++i) {
        auto p = s.evaluate(u0 + (u1 - u0) * i / 10.0, v0 + (v1 - v0) * j / 10.0);
        std::cout << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
      }
  } catch (const surfkit::Error& e) {
    std::cerr << "surfkit error " << e.status() << ": " << e.what() << "\n";
    return 1;
  }
  return 0;
}
