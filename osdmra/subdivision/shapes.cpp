#include "osdmra/subdivision/shapes.h"

#include <cmath>
#include <map>
#include <random>

#include "osdmra/base/error.h"

namespace osdmra {
namespace shapes {

namespace {

TriMesh make(const std::vector<std::array<double, 3>>& v,
             const std::vector<std::array<int, 3>>& f) {
  TriMesh m;
  m.V.resize(static_cast<Eigen::Index>(v.size()), 3);
  m.F.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int c = 0; c < 3; ++c) m.V(static_cast<Eigen::Index>(i), c) = v[i][c];
  for (std::size_t i = 0; i < f.size(); ++i)
    for (int c = 0; c < 3; ++c) m.F(static_cast<Eigen::Index>(i), c) = f[i][c];
  return m;
}

// A grid of (nu x nv) vertices with quads split along one diagonal; wraps in u
// and/or v. pos(i, j) gives the coordinates.
template <class Pos>
TriMesh grid(int nu, int nv, bool wrapU, bool wrapV, Pos pos) {
  std::vector<std::array<double, 3>> v;
  std::vector<std::array<int, 3>> f;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) v.push_back(pos(i, j));
  auto id = [&](int i, int j) { return (j % nv) * nu + (i % nu); };
  for (int j = 0; j < (wrapV ? nv : nv - 1); ++j)
    for (int i = 0; i < (wrapU ? nu : nu - 1); ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      f.push_back({a, b, c});
      f.push_back({a, c, d});
    }
  return make(v, f);
}

}  // namespace

TriMesh tetrahedron() {
  return make({{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}},
              {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}});
}

TriMesh octahedron() {
  return make(
      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
      {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}});
}

TriMesh icosahedron() {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  return make({{-1, t, 0},
               {1, t, 0},
               {-1, -t, 0},
               {1, -t, 0},
               {0, -1, t},
               {0, 1, t},
               {0, -1, -t},
               {0, 1, -t},
               {t, 0, -1},
               {t, 0, 1},
               {-t, 0, -1},
               {-t, 0, 1}},
              {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
               {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
               {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}});
}

TriMesh torus(int around, int along) {
  if (around < 3 || along < 3) throw Error("torus needs at least 3 x 3 vertices");
  return grid(around, along, true, true, [&](int i, int j) {
    const double u = 2 * M_PI * i / around, v = 2 * M_PI * j / along;
    const double r = 2.0 + 0.7 * std::cos(v);
    return std::array<double, 3>{r * std::cos(u), r * std::sin(u), 0.7 * std::sin(v)};
  });
}

TriMesh disc(int cells) {
  return grid(cells + 1, cells + 1, false, false, [&](int i, int j) {
    return std::array<double, 3>{double(i), double(j), 0.1 * ((i * 7 + j * 3) % 5)};
  });
}

TriMesh cylinder(int around, int along) {
  if (around < 3 || along < 2) throw Error("cylinder needs at least 3 x 2 vertices");
  return grid(around, along, true, false, [&](int i, int j) {
    const double u = 2 * M_PI * i / around;
    return std::array<double, 3>{std::cos(u), std::sin(u), double(j)};
  });
}

TriMesh slab(int genus) {
  if (genus < 1) throw Error("slab needs genus >= 1");
  // Cells of a (2 genus + 1) x 3 strip, with holes at (2k+1, 1); the closed surface
  // of the one-cell-thick solid, each unit square split in two triangles.
  const int W = 2 * genus + 1, H = 3;
  auto filled = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= W || y >= H) return false;
    return !(y == 1 && x % 2 == 1);
  };
  std::map<std::array<int, 3>, int> index;
  std::vector<std::array<double, 3>> v;
  std::vector<std::array<int, 3>> f;
  auto vid = [&](int x, int y, int z) {
    const std::array<int, 3> key{x, y, z};
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    index[key] = static_cast<int>(v.size());
    v.push_back({double(x), double(y), double(z)});
    return static_cast<int>(v.size()) - 1;
  };
  // A quad given counter-clockwise seen from outside.
  auto quad = [&](std::array<int, 3> a, std::array<int, 3> b, std::array<int, 3> c,
                  std::array<int, 3> d) {
    const int ia = vid(a[0], a[1], a[2]), ib = vid(b[0], b[1], b[2]), ic = vid(c[0], c[1], c[2]),
              id = vid(d[0], d[1], d[2]);
    f.push_back({ia, ib, ic});
    f.push_back({ia, ic, id});
  };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      if (!filled(x, y)) continue;
      quad({x, y, 1}, {x + 1, y, 1}, {x + 1, y + 1, 1}, {x, y + 1, 1});  // top, +z
      quad({x, y, 0}, {x, y + 1, 0}, {x + 1, y + 1, 0}, {x + 1, y, 0});  // bottom, -z
      if (!filled(x - 1, y)) quad({x, y, 0}, {x, y, 1}, {x, y + 1, 1}, {x, y + 1, 0});
      if (!filled(x + 1, y))
        quad({x + 1, y, 0}, {x + 1, y + 1, 0}, {x + 1, y + 1, 1}, {x + 1, y, 1});
      if (!filled(x, y - 1)) quad({x, y, 0}, {x + 1, y, 0}, {x + 1, y, 1}, {x, y, 1});
      if (!filled(x, y + 1))
        quad({x, y + 1, 0}, {x, y + 1, 1}, {x + 1, y + 1, 1}, {x + 1, y + 1, 0});
    }
  return make(v, f);
}

TriMesh valences() {
  // A 10-gon bipyramid (apex valence 10), then vertices inserted into chosen faces:
  // each insertion adds a valence-3 vertex and raises its face's corners by one.
  std::vector<std::array<double, 3>> v;
  std::vector<std::array<int, 3>> f;
  const int n = 10, N = 10, S = 11;
  for (int i = 0; i < n; ++i)
    v.push_back({std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 0.0});
  v.push_back({0, 0, 1.5});
  v.push_back({0, 0, -1.5});
  for (int i = 0; i < n; ++i) {
    f.push_back({i, (i + 1) % n, N});
    f.push_back({(i + 1) % n, i, S});
  }
  auto insert = [&](int face) {
    const auto [a, b, c] = f[face];
    const int x = static_cast<int>(v.size());
    std::array<double, 3> p{};
    for (int k = 0; k < 3; ++k) p[k] = (v[a][k] + v[b][k] + v[c][k]) / 3.0 * 1.15;
    v.push_back(p);
    f[face] = {a, b, x};
    f.push_back({b, c, x});
    f.push_back({c, a, x});
  };
  // South faces (2i+1) only, so the north apex keeps valence 10.
  insert(1);   // (1,0,S): v0, v1 -> 5
  insert(3);   // (2,1,S): v1 -> 6, v2 -> 5
  insert(5);   // (3,2,S): v2 -> 6, v3 -> 5
  insert(1);   // (1,0,x): v0 -> 6, v1 -> 7
  insert(1);   // again:   v0 -> 7, v1 -> 8
  insert(1);   // again:   v0 -> 8, v1 -> 9
  insert(24);  // (2,S,x) made by the third insertion: v2 -> 7
  insert(7);   // (4,3,S): v3 -> 6, v4 -> 5
  insert(9);   // (5,4,S): v4 -> 6, v5 -> 5
  return make(v, f);
}

std::vector<std::pair<std::string, TriMesh>> all() {
  return {{"tetrahedron", tetrahedron()},
          {"octahedron", octahedron()},
          {"icosahedron", icosahedron()},
          {"torus", torus()},
          {"genus2", slab(2)},
          {"genus3", slab(3)},
          {"disc", disc()},
          {"cylinder", cylinder()},
          {"valences", valences()}};
}

TriMesh byName(const std::string& name) {
  for (auto& [n, m] : all())
    if (n == name) return m;
  throw Error("unknown shape '" + name + "'");
}

}  // namespace shapes

TriMesh subdivide(const TriMesh& base, int levels, Scheme scheme, double amplitude,
                  std::uint64_t seed) {
  Hierarchy h(base.F, static_cast<int>(base.V.rows()), levels);
  std::mt19937_64 rng(seed);
  // Uniform in [-1, 1] from the raw 64-bit stream: the same numbers on every
  // standard library (std::uniform_real_distribution is implementation-defined).
  auto uniform = [&]() { return static_cast<double>(rng() >> 11) * 0x1.0p-52 - 1.0; };
  const double scale = amplitude * boundingBoxDiagonal(base.V);
  Points c = base.V;
  for (int j = 0; j < levels; ++j) {
    Points next = h.refinement(scheme, j) * c;
    if (amplitude > 0.0) {
      const double a = scale * std::ldexp(1.0, -j);
      for (Eigen::Index i = c.rows(); i < next.rows(); ++i)
        for (int k = 0; k < 3; ++k) next(i, k) += a * uniform();
    }
    c = std::move(next);
  }
  return TriMesh{c, h.faces(levels), Points()};
}

}  // namespace osdmra
