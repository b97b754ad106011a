// Placement (placement.h): the interpolation of M^J by a level-of-detail mesh, and the
// least-squares fit of its vertices.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>

#include "osdmra/base/error.h"
#include "osdmra/geometry/distance.h"
#include "osdmra/geometry/self_intersection.h"
#include "osdmra/mesh/connectivity.h"
#include "osdmra/mra/approximation.h"
#include "osdmra/mra/placement.h"
#include "osdmra/subdivision/shapes.h"

using namespace osdmra;

namespace {

KeepMask randomMask(const Hierarchy& h, unsigned seed, double density) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  KeepMask keep(h.levels());
  for (int j = 0; j < h.levels(); ++j)
    for (int e = 0; e < h.numVertices(j + 1) - h.numVertices(j); ++e)
      keep[j].push_back(u(rng) < density ? 1 : 0);
  return keep;
}

Points gather(const Points& V, const std::vector<int>& rows) {
  Points out(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t k = 0; k < rows.size(); ++k)
    out.row(static_cast<Eigen::Index>(k)) = V.row(rows[k]);
  return out;
}

// A rough subdivided icosahedron analysed with quasi-wavelets: what the approximator
// tests below place levels of detail of. Holds the hierarchy its filter bank points
// to, so it is neither copied nor moved.
struct RoughIcosahedron {
  TriMesh base, surface;
  Hierarchy h;
  FilterBank bank;
  Decomposition d;
  RoughIcosahedron(Scheme s, int levels, double roughness, unsigned seed)
      : base(shapes::byName("icosahedron")),
        surface(subdivide(base, levels, s, roughness, seed)),
        h(base.F, static_cast<int>(base.V.rows()), levels),
        bank(makeFilterBank(h, s, {WaveletKind::Quasi, 1})),
        d(analyze(bank, surface.V)) {}
  RoughIcosahedron(const RoughIcosahedron&) = delete;
  RoughIcosahedron& operator=(const RoughIcosahedron&) = delete;
};

}  // namespace

// Rows are barycentric (non-negative, sum 1), the mesh's own vertices interpolate
// themselves, and a function linear on every base triangle (the base mesh refined by
// the linear scheme) is reproduced exactly at every level-J vertex: a wrong face or a
// wrong green half would put some vertex elsewhere.
TEST(Placement, InterpolationReproducesFunctionsLinearOnTheBase) {
  for (const auto& [name, shape] : shapes::all()) {
    SCOPED_TRACE(name);
    const int J = 3;
    const Hierarchy h(shape.F, static_cast<int>(shape.V.rows()), J);
    const Points fine = subdivide(shape, J, Scheme::Linear).V;
    for (double density : {0.0, 0.05, 0.3, 1.0}) {
      const LodMesh lod = extractLod(h, randomMask(h, 11, density));
      const SparseMatrix L = lodInterpolation(h, lod);
      ASSERT_EQ(L.rows(), h.numVertices(J));
      ASSERT_EQ(L.cols(), static_cast<Eigen::Index>(lod.vertices.size()));
      for (int v = 0; v < L.rows(); ++v) {
        double sum = 0;
        for (SparseMatrix::InnerIterator it(L, v); it; ++it) {
          EXPECT_GE(it.value(), 0.0);
          sum += it.value();
        }
        EXPECT_NEAR(sum, 1.0, 1e-12) << "vertex " << v;
      }
      for (std::size_t k = 0; k < lod.vertices.size(); ++k)
        EXPECT_EQ(L.coeff(lod.vertices[k], static_cast<Eigen::Index>(k)), 1.0);
      const Points x = gather(fine, lod.vertices);
      EXPECT_LT((L * x - fine).cwiseAbs().maxCoeff(), 1e-12) << "density " << density;
    }
  }
}

// A target the mesh can represent is recovered from a perturbed start; otherwise the
// fit's residual is never above the start's.
TEST(Placement, FitRecoversRepresentableTargetsAndLowersTheResidual) {
  const TriMesh base = shapes::byName("torus");
  const int J = 3;
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
  const LodMesh lod = extractLod(h, randomMask(h, 4, 0.1));
  const SparseMatrix L = lodInterpolation(h, lod);
  const Points truth = Points::Random(L.cols(), 3);
  const Points start = truth + 0.1 * Points::Random(L.cols(), 3);
  FitOptions exact;
  exact.iterations = 1000;
  exact.tolerance = 1e-14;
  EXPECT_LT((fitPositions(L, L * truth, start, exact) - truth).cwiseAbs().maxCoeff(), 1e-8);
  const Points target = L * truth + 0.05 * Points::Random(L.rows(), 3);
  const Points fit = fitPositions(L, target, start);
  EXPECT_LT((L * fit - target).norm(), (L * start - target).norm());
  EXPECT_THROW(fitPositions(L, target.topRows(3), start), Error);
}

// Through the approximator: the same meshes as on the truncated surface, closer to the
// full-resolution surface at its vertices (both schemes).
TEST(Placement, FitLowersTheApproximationsResidual) {
  for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
    SCOPED_TRACE(schemeName(s));
    const RoughIcosahedron shape(s, 4, 0.04, 21);
    const Hierarchy& h = shape.h;
    const FilterBank& bank = shape.bank;
    const Decomposition& d = shape.d;
    const Approximator onSurface(bank, d);
    ApproximationOptions o;
    o.placement = Placement::Fit;
    const Approximator fitted(bank, d, o);
    const Points& full = onSurface.fullResolution().V;
    for (long long budget : {100LL, 400LL, 1500LL}) {
      const Approximation a = onSurface.budget(budget), b = fitted.budget(budget);
      EXPECT_EQ(a.mesh.F, b.mesh.F);
      const SparseMatrix L = lodInterpolation(h, a.lod);
      EXPECT_LT((L * b.mesh.V - full).norm(), (L * a.mesh.V - full).norm()) << budget;
    }
  }
}

// Closest on a flat full surface (a plane grid): every level-J point goes onto the
// plane, so the level of detail ends on it exactly (its vertices are level-J points);
// tangentially they stay near where they were.
TEST(Placement, ClosestPutsTheLevelOfDetailOnAPlane) {
  TriMesh base = shapes::disc(4);
  base.V.col(2).setZero();  // flat
  const int J = 3;
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
  const LodMesh lod = extractLod(h, randomMask(h, 7, 0.2));
  const SparseMatrix L = lodInterpolation(h, lod);
  TriMesh full;
  full.F = h.faces(J);
  full.V = subdivide(base, J, Scheme::Linear).V;  // canonical order, as h
  const ClosestTarget target(full);
  Points start = gather(full.V, lod.vertices);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  for (Eigen::Index v = 0; v < start.rows(); ++v) start(v, 2) += u(rng);
  FitOptions o;
  o.iterations = 500;
  o.tolerance = 1e-14;
  const Points x = fitToClosestPoints(L, lod.compactFaces, target, start, o);
  EXPECT_LT(x.col(2).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((x.leftCols(2) - start.leftCols(2)).cwiseAbs().maxCoeff(), 0.02);
  EXPECT_EQ(parsePlacement("closest"), Placement::Closest);
  EXPECT_STREQ(placementName(Placement::Closest), "closest");
}

// An open surface: a level of detail whose rim starts past the surface's rim (in its
// plane, where matching to the tangent plane costs nothing) is brought back onto it,
// since a match on the rim is taken point to point. Matched to the tangent planes
// there, a rim slid past the surface's edge (the lion's open scan over 300 faces at
// 1,667 triangles: Hausdorff 1.3e-2 of its diagonal after the fit, 3.8e-2 after the
// rounds, all at the rim; 1.0e-2 now).
TEST(Placement, ClosestBringsTheRimBackOntoAnOpenSurface) {
  TriMesh base = shapes::disc(4);
  base.V.col(2).setZero();
  const int J = 3;
  const Hierarchy h(base.F, static_cast<int>(base.V.rows()), J);
  TriMesh full;
  full.F = h.faces(J);
  full.V = subdivide(base, J, Scheme::Linear).V;
  const ClosestTarget target(full);
  const TriangleBvh& bvh = target.bvh;
  const Connectivity c(full.F, static_cast<int>(full.V.rows()));
  KeepMask keep(J);
  for (int j = 0; j < J; ++j) keep[j].assign(h.numVertices(j + 1) - h.numVertices(j), j < 1);
  const LodMesh lod = extractLod(h, keep);  // M^1
  const SparseMatrix L = lodInterpolation(h, lod);
  Points start = gather(full.V, lod.vertices);
  int rim = 0;
  for (std::size_t i = 0; i < lod.vertices.size(); ++i)
    if (c.isBoundaryVertex(lod.vertices[i])) {
      start.row(static_cast<Eigen::Index>(i)) *= 1.1;  // out past the rim, in the plane
      ++rim;
    }
  ASSERT_GT(rim, 3);
  auto farthest = [&](const Points& X) {
    double d = 0;
    for (Eigen::Index v = 0; v < X.rows(); ++v)
      d = std::max(d, bvh.closestPoint(X.row(v).transpose()).distance);
    return d;
  };
  const Points x = fitToClosestPoints(L, lod.compactFaces, target, start);
  EXPECT_LT(farthest(x), 0.2 * farthest(start));
  EXPECT_LT(x.col(2).cwiseAbs().maxCoeff(), 1e-9);  // and stays in the plane
}

// Through the approximator, both schemes: the same meshes as the fit's, no face turned
// over against the fit's, the level-J points (what the rounds fit) no farther from the
// full surface, and the sampled distance lower on a smooth surface. (On a rough one, a
// noise of 4% per level, the sampled distance at 1,500 of 5,120 triangles came out 12%
// higher for the polyhedral scheme: the level-J points and area samples disagree there.)
TEST(Placement, ClosestTurnsNoFaceOverAndComesCloser) {
  for (Scheme s : {Scheme::Loop, Scheme::Linear}) {
    for (double roughness : {0.01, 0.04}) {
      SCOPED_TRACE(std::string(schemeName(s)) + " " + std::to_string(roughness));
      const RoughIcosahedron shape(s, 4, roughness, 21);
      const Hierarchy& h = shape.h;
      const FilterBank& bank = shape.bank;
      const Decomposition& d = shape.d;
      ApproximationOptions fit, closest;
      fit.placement = Placement::Fit;
      closest.placement = Placement::Closest;
      const Approximator a(bank, d, fit), b(bank, d, closest);
      const TriMesh& full = a.fullResolution();
      const TriangleBvh bvh(full);
      for (long long budget : {100LL, 400LL, 1500LL}) {
        const Approximation x = a.budget(budget), y = b.budget(budget);
        ASSERT_EQ(x.mesh.F, y.mesh.F);
        for (Eigen::Index f = 0; f < x.mesh.F.rows(); ++f) {
          auto normal = [&](const Points& V) {
            const Eigen::Vector3d p = V.row(x.mesh.F(f, 0)), q = V.row(x.mesh.F(f, 1)),
                                  r = V.row(x.mesh.F(f, 2));
            return Eigen::Vector3d((q - p).cross(r - p));
          };
          ASSERT_GT(normal(x.mesh.V).dot(normal(y.mesh.V)), 0) << budget << " face " << f;
        }
        const SparseMatrix L = lodInterpolation(h, x.lod);
        auto squared = [&](const Points& V) {
          const Points at = L * V;
          double sum = 0;
          for (Eigen::Index i = 0; i < at.rows(); ++i)
            sum += std::pow(bvh.closestPoint(at.row(i).transpose()).distance, 2);
          return sum;
        };
        EXPECT_LE(squared(y.mesh.V), squared(x.mesh.V)) << budget;
        if (roughness > 0.02) continue;
        DistanceOptions dist;
        dist.samples = 5000;
        EXPECT_LT(surfaceDistance(y.mesh, full, dist).rmsRelative,
                  surfaceDistance(x.mesh, full, dist).rmsRelative)
            << budget;
      }
    }
  }
}

// Levels looks up, per vertex, the closest fit of the finest level's uniform mesh
// around it. Exact where the level of detail is a uniform level: the base mesh (no
// coefficient kept) is placed as Closest places it, and the whole hierarchy (every
// coefficient) is the full surface itself; between, the faces are Surface's.
TEST(Placement, LevelsIsClosestOnUniformLevels) {
  for (Scheme s : {Scheme::Linear, Scheme::Loop}) {
    SCOPED_TRACE(schemeName(s));
    const RoughIcosahedron shape(s, 3, 0.02, 5);
    const FilterBank& bank = shape.bank;
    const Decomposition& d = shape.d;
    ApproximationOptions closestOptions, levelsOptions;
    closestOptions.placement = Placement::Closest;
    levelsOptions.placement = Placement::Levels;
    const Approximator closest(bank, d, closestOptions), levels(bank, d, levelsOptions),
        plain(bank, d);
    levels.prepare();
    const Approximation b0 = closest.keepCount(0), b1 = levels.keepCount(0);
    ASSERT_EQ(b0.mesh.F, b1.mesh.F);
    EXPECT_LT((b0.mesh.V - b1.mesh.V).cwiseAbs().maxCoeff(), 1e-12);
    const Approximation all = levels.keepFraction(1.0);
    const TriMesh& full = levels.fullResolution();
    ASSERT_EQ(all.mesh.V.rows(), full.V.rows());
    EXPECT_EQ(all.mesh.V, full.V);
    // An approximator left to fit its levels on first use (only those an extraction
    // needs, on both cores) places every vertex as the prepared one does, exactly.
    const Approximator lazy(bank, d, levelsOptions);
    for (long long budget : {80LL, 300LL, 900LL}) {
      const Approximation x = plain.budget(budget), y = levels.budget(budget),
                          z = lazy.budget(budget);
      ASSERT_EQ(x.mesh.F, y.mesh.F) << budget;
      ASSERT_TRUE(y.mesh.V.allFinite());
      ASSERT_EQ(z.mesh.F, y.mesh.F) << budget;
      EXPECT_EQ(z.mesh.V, y.mesh.V) << budget;
    }
  }
  EXPECT_EQ(parsePlacement("levels"), Placement::Levels);
  EXPECT_STREQ(placementName(Placement::Levels), "levels");
}

// A move that would push one face through another is shortened (half, a quarter, ...,
// then none), vertex by vertex of the faces that newly cross; moves that cross nothing
// stay, and a pair that already crossed at the start does not hold anything back.
TEST(Placement, WithoutNewCrossingsTakesBackWhatWouldCross) {
  // Two triangles one above the other (z = 0 and z = 1), and a third far away.
  Points from(9, 3);
  from << 0, 0, 0, 1, 0, 0, 0, 1, 0,          //
      0.2, 0.2, 1, 1.2, 0.2, 1, 0.2, 1.2, 1,  //
      5, 5, 5, 6, 5, 5, 5, 6, 5;
  Faces F(3, 3);
  F << 0, 1, 2, 3, 4, 5, 6, 7, 8;
  Points to = from;
  to(3, 2) = -1;  // vertex 3 pushed through the lower triangle
  to(6, 0) = 4;   // the far triangle only moves
  const Points out = withoutNewCrossings(F, from, to);
  // Half the way (z = 0) still meets the lower triangle; a quarter (z = 0.5) does not.
  EXPECT_EQ(out.row(3), Eigen::RowVector3d(0.2, 0.2, 0.5));
  EXPECT_EQ(out.row(4), from.row(4));  // its face's other corners had not moved
  EXPECT_EQ(out.row(6), to.row(6));
  TriMesh m;
  m.V = out;
  m.F = F;
  EXPECT_EQ(findSelfIntersections(m, 0).count, 0);
  // Starting from that crossing, the same pair may stay crossed while its vertices move.
  Points crossed = to;
  Points further = to;
  further(4, 2) = 0.9;
  const Points kept = withoutNewCrossings(F, crossed, further);
  EXPECT_EQ(kept.row(4), further.row(4));
  EXPECT_EQ(withoutNewCrossings(Faces(0, 3), from, to), to);
}

// Placement::Closest matches the level of detail to the surface it is given
// (ApproximationOptions::closestTarget; lodForBudget gives the input it remeshed): the
// full surface given as the target (so matched at area samples of it too) places the
// level of detail as close to it as without one, within 2% (closer here); a target
// moved off the full surface (by 1% of the diagonal) draws the level of detail to it,
// far closer to it than the one matched to the full surface.
TEST(Placement, ClosestMatchesTheTargetItIsGiven) {
  const RoughIcosahedron shape(Scheme::Linear, 3, 0.02, 5);
  ApproximationOptions options;
  options.placement = Placement::Closest;
  const Approximator own(shape.bank, shape.d, options);
  const TriMesh& full = own.fullResolution();
  ApproximationOptions same = options, moved = options;
  same.closestTarget = std::make_shared<const TriMesh>(full);
  TriMesh off = full;
  const double diagonal = (full.V.colwise().maxCoeff() - full.V.colwise().minCoeff()).norm();
  off.V.col(0).array() += 0.01 * diagonal;
  moved.closestTarget = std::make_shared<const TriMesh>(off);
  const Approximator given(shape.bank, shape.d, same), follows(shape.bank, shape.d, moved);
  DistanceOptions dist;
  dist.samples = 5000;
  for (long long budget : {300LL, 900LL}) {
    const Approximation a = own.budget(budget), b = given.budget(budget),
                        c = follows.budget(budget);
    ASSERT_EQ(a.mesh.F, b.mesh.F);
    const double da = surfaceDistance(a.mesh, full, dist).rmsRelative,
                 db = surfaceDistance(b.mesh, full, dist).rmsRelative;
    EXPECT_LT(db, 1.02 * da) << budget;
    ASSERT_EQ(a.mesh.F, c.mesh.F);
    EXPECT_LT(surfaceDistance(c.mesh, off, dist).rmsRelative,
              0.5 * surfaceDistance(a.mesh, off, dist).rmsRelative)
        << budget;
  }
}

namespace {

// `mesh` with every face whose centroid has x > 0 split at its centroid into three,
// `times` times over: the same surface, its vertices crowded on one side.
TriMesh crowdedOnOneSide(const TriMesh& mesh, int times) {
  TriMesh m = mesh;
  for (int t = 0; t < times; ++t) {
    std::vector<Eigen::RowVector3d> V;
    std::vector<Eigen::RowVector3i> F;
    for (Eigen::Index v = 0; v < m.V.rows(); ++v) V.push_back(m.V.row(v));
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      const Eigen::RowVector3i c = m.F.row(f);
      const Eigen::RowVector3d mid = (m.V.row(c(0)) + m.V.row(c(1)) + m.V.row(c(2))) / 3;
      if (!(mid(0) > 0)) {
        F.push_back(c);
        continue;
      }
      const int o = static_cast<int>(V.size());
      V.push_back(mid);
      for (int k = 0; k < 3; ++k) F.emplace_back(c(k), c((k + 1) % 3), o);
    }
    m.V.resize(static_cast<Eigen::Index>(V.size()), 3);
    m.F.resize(static_cast<Eigen::Index>(F.size()), 3);
    for (std::size_t v = 0; v < V.size(); ++v) m.V.row(static_cast<Eigen::Index>(v)) = V[v];
    for (std::size_t f = 0; f < F.size(); ++f) m.F.row(static_cast<Eigen::Index>(f)) = F[f];
  }
  return m;
}

}  // namespace

// A target's points are its vertices, then the area samples asked for: those of
// samplePoints with seed 1, bit for bit.
TEST(Placement, ClosestTargetMatchesItsVerticesAndSamples) {
  const TriMesh mesh = shapes::byName("icosahedron");
  EXPECT_EQ(ClosestTarget(mesh).points, mesh.V);
  const ClosestTarget target(mesh, 50);
  ASSERT_EQ(target.points.rows(), mesh.V.rows() + 50);
  EXPECT_EQ(target.points.topRows(mesh.V.rows()), mesh.V);
  EXPECT_EQ(target.points.bottomRows(50), samplePoints(mesh, 50, 1));
}

// Matched at area samples of the target besides its vertices (as many as the full
// surface has vertices), the rounds bring the level of detail closer to the surface by
// the sampled distance it is measured with than at the vertices alone, whether the
// target's vertices are spread evenly or crowd on one side (its faces there split at
// their centroids twice over: nine times as many vertices, the same surface). Matched at
// its vertices alone, a scan's crowds pulled the level of detail and left it loose
// between them (lod_scans: docs/LOD.md).
TEST(Placement, ClosestComesCloserMatchedAtAreaSamples) {
  const RoughIcosahedron shape(Scheme::Linear, 3, 0.02, 5);
  ApproximationOptions fit;
  fit.placement = Placement::Fit;
  const Approximator a(shape.bank, shape.d, fit);
  const TriMesh& full = a.fullResolution();
  const TriMesh crowded = crowdedOnOneSide(full, 2);
  ASSERT_GT(crowded.V.rows(), 3 * full.V.rows());
  const int samples = static_cast<int>(full.V.rows());
  const ClosestTarget even(full), atVertices(crowded), evenSampled(full, samples),
      sampled(crowded, samples);
  DistanceOptions dist;
  dist.samples = 20000;
  for (long long budget : {300LL, 900LL}) {
    const Approximation x = a.budget(budget);
    const SparseMatrix L = lodInterpolation(shape.h, x.lod);
    const Points p = fitToClosestPoints(L, x.mesh.F, even, x.mesh.V),
                 q = fitToClosestPoints(L, x.mesh.F, atVertices, x.mesh.V),
                 ps = fitToClosestPoints(L, x.mesh.F, evenSampled, x.mesh.V),
                 r = fitToClosestPoints(L, x.mesh.F, sampled, x.mesh.V);
    auto rms = [&](const Points& V) {
      TriMesh m = x.mesh;
      m.V = V;
      return surfaceDistance(m, full, dist).rmsRelative;
    };
    EXPECT_LT(rms(ps), rms(p)) << budget;
    EXPECT_LT(rms(r), rms(q)) << budget;
  }
}
