// Writes the stock meshes of geometry/meshes/ (ASCII OFF for 3D, .poly2d for 2D).
// Usage: varsph_make_meshes OUTPUT_DIR
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace {
struct P3 { double x, y, z; };
struct Mesh { std::vector<P3> v; std::vector<std::vector<int>> f; };

// axis-aligned box [lo, hi] as 12 outward triangles, appended to m
void add_box(Mesh& m, P3 lo, P3 hi) {
  const int b = static_cast<int>(m.v.size());
  for (int i = 0; i < 8; ++i)
    m.v.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (auto& f : q) {
    m.f.push_back({b + f[0], b + f[1], b + f[2]});
    m.f.push_back({b + f[0], b + f[2], b + f[3]});
  }
}

void write_off(const std::string& path, const Mesh& m, const std::string& comment) {
  std::ofstream o(path);
  o.precision(17);
  o << "OFF\n# " << comment << "\n" << m.v.size() << " " << m.f.size() << " 0\n";
  for (auto& p : m.v) o << p.x << " " << p.y << " " << p.z << "\n";
  for (auto& f : m.f) {
    o << f.size();
    for (int i : f) o << " " << i;
    o << "\n";
  }
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) { std::fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]); return 2; }
  const std::string dir = argv[1];
  {  // SPHERIC test 2 (Kleefsman et al. 2005): tank and obstacle as two closed boxes
    Mesh tank; add_box(tank, {0, 0, 0}, {3.22, 1.0, 1.0});
    write_off(dir + "/spheric2_tank.off", tank, "SPHERIC benchmark 2 tank, 3.22 x 1.0 x 1.0 m, x along the length");
    Mesh box; add_box(box, {0.6635, 0.5 - 0.2015, 0.0}, {0.6635 + 0.161, 0.5 + 0.2015, 0.161});
    write_off(dir + "/spheric2_obstacle.off", box, "SPHERIC benchmark 2 box obstacle 0.161 x 0.403 x 0.161 m");
    Mesh water; add_box(water, {3.22 - 1.228, 0, 0}, {3.22, 1.0, 0.55});
    write_off(dir + "/spheric2_water.off", water, "SPHERIC benchmark 2 water column 1.228 x 1.0 x 0.55 m");
  }
  {  // sloshing tank 0.6 x 0.3 x 0.4 m
    Mesh t; add_box(t, {0, 0, 0}, {0.6, 0.3, 0.4});
    write_off(dir + "/sloshing_tank.off", t, "rectangular sloshing tank 0.6 x 0.3 x 0.4 m");
  }
  {  // closed cylinder, radius 0.25 m, height 0.5 m, axis z, 64 sides
    const int n = 64;
    const double R = 0.25, H = 0.5;
    Mesh c;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n;
      c.v.push_back({R * std::cos(a), R * std::sin(a), 0});
      c.v.push_back({R * std::cos(a), R * std::sin(a), H});
    }
    c.v.push_back({0, 0, 0});
    c.v.push_back({0, 0, H});
    const int b = 2 * n, t = 2 * n + 1;
    for (int i = 0; i < n; ++i) {
      const int j = (i + 1) % n;
      c.f.push_back({2 * i, 2 * j, 2 * j + 1});
      c.f.push_back({2 * i, 2 * j + 1, 2 * i + 1});
      c.f.push_back({b, 2 * j, 2 * i});
      c.f.push_back({t, 2 * i + 1, 2 * j + 1});
    }
    write_off(dir + "/cylinder.off", c, "closed cylinder R = 0.25 m, H = 0.5 m, axis z, 64 sides");
  }
  {  // 2D tank of the paper: floor 0.58 m, walls 0.6 m, open top
    std::ofstream o(dir + "/tank2d.poly2d");
    o << "# varsph 2D tank: floor 0.58 m, walls 0.6 m high, open top.\n"
         "# Walking direction left wall down, floor, right wall up: the outward normal (right-hand\n"
         "# side) points away from the fluid.\nopen\n0 0.6\n0 0\n0.58 0\n0.58 0.6\n";
  }
  return 0;
}
