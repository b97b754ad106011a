// Remeshing to subdivision connectivity (remesh.h): topology kept, the result has
// exactly the requested structure, no triangle flipped, of zero area or crossing
// another, and the distance to the input stays within stated bounds on smooth shapes
// of genus 0, 1 and 2, open and closed, on a cube's sharp edges and on a folded input.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "osdmra/base/error.h"
#include "osdmra/geometry/distance.h"
#include "osdmra/geometry/self_intersection.h"
#include "osdmra/mesh/connectivity.h"
#include "osdmra/mesh/spatial_order.h"
#include "osdmra/remesh/features.h"
#include "osdmra/remesh/remesh.h"
#include "osdmra/remesh/simplify.h"
#include "osdmra/subdivision/recovery.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

using namespace osdmra;
using namespace osdmra::test;

namespace {

// The simplification's stages relaxed mesh-wide, and the default (vertex by vertex,
// mesh-wide where that leaves defects).
constexpr StageRelaxation kRelaxations[] = {StageRelaxation::meshWide,
                                            StageRelaxation::perVertexElseMeshWide};

// A shape refined by Loop subdivision, lightly displaced, then with its vertices
// shuffled so that it has no visible structure left to exploit.
TriMesh smoothInput(const TriMesh& base, int levels, std::uint64_t seed) {
  const TriMesh m = subdivide(base, levels, Scheme::Loop, 0.01, static_cast<int>(seed));
  return renumberVertices(m, randomPermutation(static_cast<int>(m.V.rows()), seed));
}

// The defects beyond the input's own crossings: what remesh() weighs its choices by.
long long defectsBeyondInput(const Remeshing& r) {
  return r.flippedTriangles + r.degenerateTriangles + r.selfIntersections -
         r.selfIntersectionsAtInputCrossings;
}

// A noisy genus-2 slab (1,600 faces displaced by a twentieth of its size) asked for 80
// base faces at J = 3, its noise's folds left in (taken out, unfold.h, no remesh of it
// leaves a defect): its base stops over size, and its remeshes fold.
struct NoisySlab {
  TriMesh input = subdivide(shapes::slab(2), 2, Scheme::Loop, 0.05, 6);
  RemeshOptions options = [] {
    RemeshOptions o;
    o.baseFaces = 80;
    o.levels = 3;
    o.unfoldInput = false;
    return o;
  }();
};

}  // namespace

TEST(Remesh, KeepsTopologyAndStaysClose) {
  struct Case {
    const char* name;
    TriMesh base;
    int levels;
  };
  const Case cases[] = {{"sphere-like (icosahedron)", shapes::icosahedron(), 4},
                        {"torus", shapes::torus(), 3},
                        {"genus 2", shapes::slab(2), 3},
                        {"open disc", shapes::disc(), 4},
                        {"cylinder (two boundary loops)", shapes::cylinder(), 3}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const TriMesh input = smoothInput(c.base, c.levels, 7);
    validate(input, c.name);
    for (const StageRelaxation stages : kRelaxations) {
      SCOPED_TRACE(static_cast<int>(stages));
      RemeshOptions o;
      o.baseFaces = std::max(40, static_cast<int>(input.F.rows() / 16));
      o.levels = 3;
      o.stages = stages;
      const Remeshing r = remesh(input, o);
      validate(r.mesh, "remeshed");
      // Sampling the bijective, distortion-bounded parameterisation folds nothing: the
      // clean-up, a safety net, has nothing to do. Vertex by vertex, a vertex passed over
      // reaches the loosest bounds early, and the grid may fold where it went (the disc:
      // 1 triangle, 11 points moved; the cylinder: 1, 15): the clean-up mends those, and
      // the remesh is kept (no defect is left, below).
      if (stages == StageRelaxation::meshWide) {
        EXPECT_EQ(r.cleanupDefectsBefore, 0);
        EXPECT_EQ(r.cleanupMovedPoints, 0);
      }
      validate(r.base, "base");
      // Topology: genus, boundary loops and components.
      const Topology a = topology(input), b = topology(r.mesh), base = topology(r.base);
      EXPECT_EQ(b, a);
      EXPECT_EQ(base.euler, a.euler);
      // The base is about the size asked for and the result is its J-fold split.
      EXPECT_LE(r.base.F.rows(), o.baseFaces);
      EXPECT_GT(r.base.F.rows(), o.baseFaces / 2);
      EXPECT_EQ(r.mesh.F.rows(), r.base.F.rows() << (2 * o.levels));
      const Recovery rec = recoverSubdivision(r.mesh.F, static_cast<int>(r.mesh.V.rows()));
      EXPECT_GE(rec.levels, o.levels) << describe(rec);
      // Close to the input, relative to the bounding-box diagonal.
      DistanceOptions d;
      d.samples = 20000;
      const SurfaceDistance dist = surfaceDistance(r.mesh, input, d);
      EXPECT_LT(dist.rmsRelative, 2e-3) << dist.rmsRelative;
      EXPECT_LT(dist.hausdorffRelative, 2e-2) << dist.hausdorffRelative;
      // No triangle turned over, of zero area, or crossing another.
      EXPECT_EQ(r.degenerateTriangles, 0);
      EXPECT_EQ(r.flippedTriangles, 0);
      EXPECT_EQ(r.selfIntersections, 0);
      // The base mesh is the remeshed surface's level 0, and on the input.
      EXPECT_EQ(r.base.V, r.mesh.V.topRows(r.base.V.rows()));
      const TriangleBvh bvh(input);
      const double diag = boundingBoxDiagonal(input.V);
      for (Eigen::Index v = 0; v < r.base.V.rows(); ++v)
        EXPECT_LT(bvh.closestPoint(r.base.V.row(v).transpose()).distance, 1e-12 * diag);
    }
  }
}

TEST(Remesh, SharpFeatureEdgesStayEdges) {
  // A cube refined linearly (flat faces, 90 degree edges): its edges are features,
  // so the base mesh follows them, the grid points on them are sampled along them,
  // and the remeshed surface is the cube itself, to rounding. Without features the
  // cube's edges get cut.
  const TriMesh cube = unitCube();
  validate(cube, "cube");
  const TriMesh input = subdivide(cube, 4, Scheme::Linear);
  RemeshOptions o;
  o.baseFaces = 100;
  o.levels = 3;
  const Remeshing r = remesh(input, o);
  EXPECT_GE(r.featureEdges, 12 * 16);
  validate(r.mesh, "remeshed cube");
  DistanceOptions d;
  d.samples = 20000;
  const SurfaceDistance dist = surfaceDistance(r.mesh, input, d);
  o.featureAngle = 180;  // features off: the cube's edges get cut
  const Remeshing smooth = remesh(input, o);
  EXPECT_EQ(smooth.featureEdges, 0);
  const SurfaceDistance cut = surfaceDistance(smooth.mesh, input, d);
  EXPECT_LT(dist.hausdorffRelative, 1e-12)
      << dist.hausdorffRelative << " cleanup " << r.cleanupDefectsBefore << " "
      << r.cleanupMovedPoints << " " << r.cleanupRelaxedFaces << " stage " << r.simplificationStage
      << " base " << r.base.F.rows();
  EXPECT_GT(cut.hausdorffRelative, 1e-2) << cut.hausdorffRelative;
}

TEST(Remesh, FoldedInputComesOutClean) {
  // A scan's fold: one vertex dragged across the far edge of one of its triangles, so
  // that the triangle faces against its corners' normals (and overlaps its
  // neighbour). The remeshed surface has no such triangle, and crosses nowhere.
  TriMesh input = subdivide(shapes::icosahedron(), 3, Scheme::Loop);
  const Connectivity c(input.F, static_cast<int>(input.V.rows()));
  const int v = 100;
  const IndexSpan ring = c.ring(v);
  const Eigen::RowVector3d mid = 0.5 * (input.V.row(ring[0]) + input.V.row(ring[1]));
  input.V.row(v) = mid + 0.3 * (mid - input.V.row(v));
  // The precondition: some face of the input now faces against its corners' normals.
  Points normals = Points::Zero(input.V.rows(), 3);
  std::vector<Eigen::Vector3d> faceNormal(input.F.rows());
  for (Eigen::Index f = 0; f < input.F.rows(); ++f) {
    const Eigen::Vector3d a = input.V.row(input.F(f, 0)), b = input.V.row(input.F(f, 1)),
                          cc = input.V.row(input.F(f, 2));
    faceNormal[f] = (b - a).cross(cc - a);
    for (int k = 0; k < 3; ++k) normals.row(input.F(f, k)) += faceNormal[f].transpose();
  }
  int folds = 0;
  for (Eigen::Index f = 0; f < input.F.rows(); ++f) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) sum += normals.row(input.F(f, k)).transpose();
    folds += faceNormal[f].dot(sum) <= 0;
  }
  ASSERT_GE(folds, 1);
  RemeshOptions o;
  o.baseFaces = 60;
  o.levels = 3;
  const Remeshing r = remesh(input, o);
  EXPECT_EQ(r.flippedTriangles, 0);
  EXPECT_EQ(r.degenerateTriangles, 0);
  EXPECT_EQ(r.selfIntersections, 0);
  EXPECT_EQ(findSelfIntersections(r.mesh).count, 0);
  EXPECT_EQ(topology(r.mesh).euler, 2);
}

// Two spheres through each other, one mesh: the remesh crosses itself where the input
// does, and nowhere else. Those pairs are the input's own (reported apart), so the
// clean-up leaves them, and the exact map is not tried for them.
TEST(Remesh, CrossingsOfTheInputAreReportedAsItsOwnAndLeftAlone) {
  const TriMesh sphere = subdivide(shapes::icosahedron(), 3, Scheme::Loop);
  TriMesh input;
  input.V.resize(2 * sphere.V.rows(), 3);
  input.F.resize(2 * sphere.F.rows(), 3);
  input.V << sphere.V, sphere.V.rowwise() + Eigen::RowVector3d(0.8, 0.1, 0.05);
  input.F << sphere.F, sphere.F.array() + static_cast<int>(sphere.V.rows());
  ASSERT_GT(findSelfIntersections(input).count, 0);
  RemeshOptions o;
  o.baseFaces = 80;
  o.levels = 3;
  const Remeshing r = remesh(input, o);
  EXPECT_GT(r.selfIntersections, 0);
  EXPECT_EQ(r.selfIntersectionsAtInputCrossings, r.selfIntersections);
  EXPECT_EQ(r.selfIntersectionsWhereSheetsCross, r.selfIntersections);
  EXPECT_EQ(r.flippedTriangles + r.degenerateTriangles, 0);
  EXPECT_EQ(r.cleanupMovedPoints, 0);
  EXPECT_EQ(r.exactDefects, -1);
}

// Where the straightened map (resample.h) leaves defects after the clean-up, the exact
// inverse of the removals is tried as well and kept only if it leaves fewer: a coarse
// torus (192 faces, displaced by a twentieth of its size) over 20 base faces at J = 3,
// where the straightened map leaves 3 defects and the exact one none. (Displaced by a
// fiftieth, it left 12 until the clean-up untangled its disks in the plane: none now.)
// Where the straightened map leaves none, the exact one is not tried.
TEST(Remesh, TheExactMapIsTriedWhereTheStraightenedOneLeavesDefects) {
  RemeshOptions o;
  o.baseFaces = 20;
  o.levels = 3;
  // This noisy torus's base of 20 faces crosses itself unless the simplification
  // refuses that (the default): with the check its remesh is clean; without it the
  // straightened map leaves defects, and the exact one is tried.
  const Remeshing checked = remesh(subdivide(shapes::torus(), 1, Scheme::Loop, 0.05, 5), o);
  EXPECT_EQ(checked.straightenedDefects, 0);
  EXPECT_EQ(checked.flippedTriangles + checked.degenerateTriangles + checked.selfIntersections, 0);
  EXPECT_EQ(findSelfIntersections(checked.base).count, 0);
  // Without the check, the base made with the mesh-wide stages crosses itself (the
  // per-vertex one does not: remesh() would keep that).
  o.baseWithoutNewCrossings = false;
  o.stages = StageRelaxation::meshWide;
  const Remeshing r = remesh(subdivide(shapes::torus(), 1, Scheme::Loop, 0.05, 5), o);
  EXPECT_GT(findSelfIntersections(r.base).count, 0);
  EXPECT_GT(r.straightenedDefects, 0);
  ASSERT_GE(r.exactDefects, 0);
  EXPECT_LT(r.exactDefects, r.straightenedDefects);
  EXPECT_EQ(r.gridMap, "exact");
  EXPECT_EQ(r.flippedTriangles + r.degenerateTriangles + r.selfIntersections, r.exactDefects);
  EXPECT_EQ(findSelfIntersections(r.mesh).count, r.selfIntersections);
  validate(r.mesh, "remeshed");
  EXPECT_EQ(r.mesh.F.rows(), r.base.F.rows() << (2 * o.levels));
  // The exact map runs beside the straightened one's repairs (on two cores): the same
  // result every time, as when it ran after them.
  const Remeshing again = remesh(subdivide(shapes::torus(), 1, Scheme::Loop, 0.05, 5), o);
  EXPECT_EQ(again.mesh.V, r.mesh.V);
  EXPECT_EQ(again.exactDefects, r.exactDefects);
  EXPECT_EQ(again.straightenedDefects, r.straightenedDefects);

  const Remeshing smooth = remesh(smoothInput(shapes::icosahedron(), 4, 7), o);
  EXPECT_EQ(smooth.straightenedDefects, 0);
  EXPECT_EQ(smooth.exactDefects, -1);
  EXPECT_EQ(smooth.gridMap, "straightened");
}

// The default relaxation (StageRelaxation::perVertexElseMeshWide) keeps the per-vertex
// remesh where it leaves no defect beyond the input's own, and the mesh-wide one where it
// does and that one leaves fewer: the noisy slab (NoisySlab), where the per-vertex remesh
// leaves defects and the mesh-wide one none. (Asked for 50, as until its short feature
// lines could go where the base is over size, both now leave none; displaced by 0.04, the
// per-vertex remesh left 9 and the mesh-wide one none until the clean-up untangled its
// disks in the plane: both none now.)
TEST(Remesh, FallsBackToTheMeshWideStagesWhereVertexByVertexLeavesDefects) {
  const NoisySlab slab;
  const TriMesh& input = slab.input;
  RemeshOptions o = slab.options;
  // Split further where its base is over size and defects are left (the next test), its
  // per-vertex remesh leaves none either: no splits here.
  o.splitFoldingFaces = false;
  o.stages = StageRelaxation::perVertex;
  const Remeshing perVertex = remesh(input, o);
  EXPECT_EQ(perVertex.stages, "vertex");
  EXPECT_EQ(perVertex.perVertexDefects, -1);  // not a fallback: not counted
  o.stages = StageRelaxation::meshWide;
  const Remeshing meshWide = remesh(input, o);
  EXPECT_EQ(meshWide.stages, "mesh");
  ASSERT_GT(defectsBeyondInput(perVertex), defectsBeyondInput(meshWide));
  o.stages = StageRelaxation::perVertexElseMeshWide;
  const Remeshing r = remesh(input, o);
  EXPECT_EQ(r.stages, "mesh");
  EXPECT_EQ(r.perVertexDefects, defectsBeyondInput(perVertex));
  EXPECT_EQ(r.mesh.V, meshWide.mesh.V);
  EXPECT_EQ(r.mesh.F, meshWide.mesh.F);
  EXPECT_EQ(defectsBeyondInput(r), defectsBeyondInput(meshWide));

  // Where vertex by vertex leaves none, it is kept, and the mesh-wide one never made.
  const TriMesh smooth = smoothInput(shapes::icosahedron(), 3, 7);
  const Remeshing kept = remesh(smooth, o);
  o.stages = StageRelaxation::perVertex;
  const Remeshing alone = remesh(smooth, o);
  EXPECT_EQ(defectsBeyondInput(alone), 0);
  EXPECT_EQ(kept.stages, "vertex");
  EXPECT_EQ(kept.perVertexDefects, 0);
  EXPECT_EQ(kept.mesh.V, alone.mesh.V);
}

// Where the base is over size whatever the splits (no vertex can go under the last
// stage) and the remesh leaves defects, splits up to 10% over the size the
// simplification stopped at are tried too, and kept where they leave fewer: the noisy
// slab above, its stages relaxed vertex by vertex, comes out with none so, where without
// splits it leaves some; its base within 10% of the size without splits, its topology
// kept.
TEST(Remesh, SplitsFurtherWhereTheBaseIsOverSizeAndDefectsAreLeft) {
  const NoisySlab slab;
  const TriMesh& input = slab.input;
  RemeshOptions o = slab.options;
  o.stages = StageRelaxation::perVertex;
  o.splitFoldingFaces = false;
  o.refineGrid = false;  // the uniform grid, whose folds the splits are chosen by
  const Remeshing without = remesh(input, o);
  ASSERT_GT(without.base.F.rows(), 1.1 * o.baseFaces) << "a base over size";
  ASSERT_GT(defectsBeyondInput(without), 0);
  o.splitFoldingFaces = true;
  const Remeshing with = remesh(input, o);
  EXPECT_EQ(defectsBeyondInput(with), 0);
  EXPECT_GT(with.baseSplits, 0);
  EXPECT_EQ(with.base.F.rows(), without.base.F.rows() + 2 * with.baseSplits);
  EXPECT_LE(with.base.F.rows(), 1.1 * without.base.F.rows());
  EXPECT_EQ(topology(with.mesh), topology(input));
  validate(with.mesh, "remeshed");
}

// A feature line on its own shorter than a base edge pins two base vertices closer
// together than the base's edges. Where the base would otherwise be over 10% of the size
// asked, remesh() drops such lines (features.h), and keeps the smaller base: a noisy
// genus-2 slab asked for 50 base faces gets 86 with 13 feature edges dropped, where the
// simplification with every feature line stops at more. A base within size keeps all.
TEST(Remesh, DropsShortFeatureLinesWhereTheBaseWouldBeOverSize) {
  const TriMesh input = subdivide(shapes::slab(2), 2, Scheme::Loop, 0.04, 7);
  RemeshOptions o;
  o.baseFaces = 50;
  o.levels = 3;
  o.stages = StageRelaxation::perVertex;
  const Remeshing r = remesh(input, o);
  EXPECT_GT(r.featureEdgesDropped, 0);

  const TriMesh ordered = inSpatialOrder(input);
  double area = 0;
  for (Eigen::Index f = 0; f < ordered.F.rows(); ++f) {
    const Eigen::Vector3d a = ordered.V.row(ordered.F(f, 0)), b = ordered.V.row(ordered.F(f, 1)),
                          c = ordered.V.row(ordered.F(f, 2));
    area += 0.5 * (b - a).cross(c - a).norm();
  }
  const double span = 0.5 * std::sqrt(4 * area / (std::sqrt(3.0) * o.baseFaces));
  remeshing::SimplifyOptions how;
  how.noNewCrossings = true;
  how.stagesPerVertex = true;
  const remeshing::Features all = remeshing::detectFeatures(ordered, o.featureAngle, span);
  const remeshing::Simplification withAll =
      remeshing::simplify(ordered, all, o.baseFaces, {}, remeshing::kStages, how);
  EXPECT_GT(withAll.base.F.rows(), 1.1 * o.baseFaces);
  EXPECT_LT(r.base.F.rows(), withAll.base.F.rows());
  EXPECT_EQ(r.featureEdges + r.featureEdgesDropped, static_cast<int>(all.list.size()));

  const Remeshing within = remesh(smoothInput(shapes::icosahedron(), 3, 7), o);
  EXPECT_LE(within.base.F.rows(), 1.1 * o.baseFaces);
  EXPECT_EQ(within.featureEdgesDropped, 0);
}

TEST(Remesh, KeepsTheTipOfAProtrusion) {
  // A sphere with a horn: one vertex pulled out to three times the radius, its
  // one-ring a sharp cone. Asked for bases far coarser than the sphere needs, the
  // simplification keeps the horn's tip rather than fold the horn into the faces
  // around it (where the grid would sample past it); if that keeps it above the size
  // asked for, it says why.
  TriMesh input = subdivide(shapes::icosahedron(), 3, Scheme::Loop);
  const Eigen::RowVector3d tip = 3 * input.V.row(0) / input.V.row(0).norm();
  input.V.row(0) = tip;
  auto keepsTip = [&](const Remeshing& r) {
    bool kept = false;
    for (Eigen::Index v = 0; v < r.base.V.rows(); ++v) kept = kept || r.base.V.row(v) == tip;
    return kept;
  };
  for (const StageRelaxation stages : kRelaxations)
    for (int baseFaces : {8, 12, 16}) {
      SCOPED_TRACE(baseFaces);
      SCOPED_TRACE(static_cast<int>(stages));
      RemeshOptions o;
      o.baseFaces = baseFaces;
      o.levels = 4;
      o.stages = stages;
      const Remeshing r = remesh(input, o);
      EXPECT_EQ(r.tips, 1);  // the horn's tip, its faces' angles summing to under 192 degrees
      EXPECT_TRUE(keepsTip(r));
      EXPECT_EQ(r.base.F.rows() > baseFaces, !r.baseSizeReason.empty());
      EXPECT_EQ(r.flippedTriangles + r.degenerateTriangles, 0);
      EXPECT_EQ(r.selfIntersections, 0);
      // The remeshed surface keeps the horn: mesh-wide 0.86, 0.82 and 0.39% of the
      // diagonal over 8, 12 and 16 base faces (2.0% over 8 until 2026-11-29, when the
      // whole sphere but the horn was five base vertices); vertex by vertex 1.43% over 12
      // faces (the base asked for 8 stops there too, saying why: the sphere's seven
      // vertices then spread by importance, not evenly) and 0.25% over 16. Flattening the
      // tip, as the simplification once did to reach 8 faces, is 6.3%.
      DistanceOptions d;
      d.samples = 20000;
      const SurfaceDistance dist = surfaceDistance(r.mesh, input, d);
      EXPECT_LT(dist.hausdorffRelative, stages == StageRelaxation::meshWide ? 0.01 : 0.02)
          << dist.hausdorffRelative;
    }
}

namespace {

// A cylinder as CAD programs and STL exports write it: n segments, the side one strip
// of 2n triangles spanning the whole height (angles of about 360 / n degrees), each
// cap a fan of n triangles into its centre (valence n).
TriMesh cadCylinder(int n, double height) {
  TriMesh m;
  m.V.resize(2 * n + 2, 3);
  m.F.resize(4 * n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    m.V.row(i) << std::cos(a), std::sin(a), 0;
    m.V.row(n + i) << std::cos(a), std::sin(a), height;
  }
  m.V.row(2 * n) << 0, 0, 0;
  m.V.row(2 * n + 1) << 0, 0, height;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.F.row(4 * i) << i, j, n + j;
    m.F.row(4 * i + 1) << i, n + j, n + i;
    m.F.row(4 * i + 2) << 2 * n, j, i;
    m.F.row(4 * i + 3) << 2 * n + 1, n + i, n + j;
  }
  return m;
}

}  // namespace

TEST(Remesh, SimplifiesAnInputMadeOfSlivers) {
  // Every side triangle of the 128-segment cylinder has an angle of 1.4 degrees, under
  // every stage's smallest flat angle (5 degrees at the loosest): until 2026-11-26 no
  // vertex could go and the base kept all 512 faces for the 60 asked. The last stage
  // lets a removal make faces as skinny as the skinniest it replaces, never skinnier.
  const TriMesh input = cadCylinder(128, 3.0);
  validate(input, "cylinder");
  for (const StageRelaxation stages : kRelaxations) {
    SCOPED_TRACE(static_cast<int>(stages));
    RemeshOptions o;
    o.baseFaces = 60;
    o.levels = 3;
    o.stages = stages;
    const Remeshing r = remesh(input, o);
    EXPECT_LE(r.base.F.rows(), 60);
    EXPECT_GT(r.base.F.rows(), 54);
    EXPECT_TRUE(r.baseSizeReason.empty()) << r.baseSizeReason;
    EXPECT_TRUE(remeshing::kStages[r.simplificationStage].orAsSkinnyAsReplaced);
    // Mesh-wide, the stage before the last (which exempts slivers from the distortion
    // bound) suffices; vertex by vertex, single vertices reach the last.
    if (stages == StageRelaxation::meshWide) {
      EXPECT_EQ(remeshing::kStages[r.simplificationStage].sliverAngle, 0.0);
    }
    EXPECT_EQ(topology(r.mesh), topology(input));
    EXPECT_EQ(r.cleanupMovedPoints, 0);
    EXPECT_EQ(r.flippedTriangles + r.degenerateTriangles + r.selfIntersections, 0);
    // The rims are feature lines: the remesh keeps the cylinder's shape.
    DistanceOptions d;
    d.samples = 20000;
    EXPECT_LT(surfaceDistance(r.mesh, input, d).hausdorffRelative, 1e-3);
  }
}

// The remesh is a function of the surface: the input is renumbered along space first
// (inSpatialOrder), so a file's vertex and face order changes nothing.
TEST(Remesh, DoesNotDependOnTheNumberingOfItsInput) {
  const TriMesh input = smoothInput(shapes::torus(), 2, 5);
  RemeshOptions o;
  o.baseFaces = 60;
  o.levels = 2;
  const Remeshing r = remesh(input, o);
  for (std::uint64_t seed : {1, 2}) {
    const Remeshing again = remesh(shuffle(input, seed), o);
    EXPECT_EQ(again.mesh.V, r.mesh.V) << "seed " << seed;
    EXPECT_EQ(again.mesh.F, r.mesh.F) << "seed " << seed;
  }
}

TEST(Remesh, RejectsBadOptions) {
  const TriMesh ico = shapes::icosahedron();
  RemeshOptions o;
  o.baseFaces = 2;
  EXPECT_THROW(remesh(ico, o), Error);
  o.baseFaces = 10;
  o.levels = 9;
  EXPECT_THROW(remesh(ico, o), Error);
  o.levels = 2;
  o.maxFaces = -1;
  EXPECT_THROW(remesh(ico, o), Error);
  o.maxFaces = 0;
  // Coordinates whose squares overflow: refused up front, not an error from deep inside.
  o.levels = 2;
  TriMesh huge = ico;
  huge.V *= 1e200;
  try {
    remesh(huge, o);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("too large for its areas"), std::string::npos) << e.what();
  }
  TriMesh large = ico;
  large.V *= 1e100;
  EXPECT_NO_THROW(remesh(large, o));
}

// As many levels as keep the output within the limit, at least 2 (or all asked if
// fewer): 5 over 300 faces within 2^19 (307,200 faces), 4 over 1,000 (256,000).
TEST(LevelsWithin, TheOutputStaysWithinTheLimit) {
  EXPECT_EQ(levelsWithin(300, 5, 1 << 19), 5);
  EXPECT_EQ(levelsWithin(512, 5, 1 << 19), 5);  // exactly 2^19
  EXPECT_EQ(levelsWithin(513, 5, 1 << 19), 4);
  EXPECT_EQ(levelsWithin(1000, 5, 1 << 19), 4);
  EXPECT_EQ(levelsWithin(2162, 5, 1 << 19), 3);
  EXPECT_EQ(levelsWithin(4, 5, 1 << 19), 5);
  EXPECT_EQ(levelsWithin(4, 3, 1 << 19), 3);
  EXPECT_EQ(levelsWithin(1 << 20, 5, 1 << 19), 2);
  EXPECT_EQ(levelsWithin(1 << 20, 1, 1 << 19), 1);
  EXPECT_EQ(levelsWithin(1 << 20, 5, 0), 5);  // no limit
}

// A base larger than asked (a torus cannot be simplified to 4 faces) is split fewer
// times under RemeshOptions::maxFaces, counted on the base made, not the one asked.
TEST(Remesh, MaxFacesCountsTheBaseMade) {
  const TriMesh torus = shapes::torus(27, 13);
  RemeshOptions o;
  o.baseFaces = 4;
  o.levels = 5;
  o.maxFaces = 2000;
  const Remeshing r = remesh(torus, o);
  const long long base = r.base.F.rows();
  ASSERT_GT(base, 4);
  EXPECT_EQ(r.levels, levelsWithin(base, 5, 2000));
  EXPECT_LT(r.levels, 5);
  EXPECT_EQ(r.mesh.F.rows(), base << (2 * r.levels));
  EXPECT_LE(r.mesh.F.rows(), 2000);
  o.maxFaces = 0;
  o.levels = 2;
  EXPECT_EQ(remesh(torus, o).levels, 2);
}

// remesh() is a library entry point: an invalid mesh (here an unreferenced vertex, which
// scans carry and which made the simplification read out of bounds) is refused with the
// element named, never a crash.
TEST(Remesh, RejectsAnInvalidMeshNamingTheElement) {
  TriMesh ico = shapes::icosahedron();
  ico.V.conservativeResize(ico.V.rows() + 1, 3);
  ico.V.row(ico.V.rows() - 1) << 5.0, 5.0, 5.0;
  RemeshOptions o;
  o.baseFaces = 10;
  o.levels = 2;
  try {
    remesh(ico, o);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 12"), std::string::npos) << e.what();
  }
}

// The grid is sampled through the straightened map (resample.h) and, where that folds
// grid triangles, through the exact inverse of the removals too; where the exact one
// folds none, its grid is the one cleaned up, and the clean-up has nothing to unfold: a
// cylinder (Loop-subdivided three times, displaced by a hundredth) over 20 base faces at
// J = 3, whose straightened grid folds 11 triangles. Where both fold (a torus, twice
// subdivided, displaced by a fiftieth: 4 and 1), the straightened grid is cleaned up, as
// the exact map samples less evenly; where the straightened one folds none, the exact
// one is not sampled. Whichever grid is cleaned up, the clean-up starts from the folds
// counted for it.
TEST(Remesh, SamplesThroughTheExactMapWhereItFoldsNothing) {
  RemeshOptions o;
  o.baseFaces = 20;
  o.levels = 3;
  o.refineGrid = false;  // the uniform grids, whose folds these shapes are made for
  auto startsFromItsFolds = [](const Remeshing& r) {
    EXPECT_EQ(r.cleanupDefectsBefore, r.gridMap == "exact" ? r.exactFolds : r.straightenedFolds);
  };
  const Remeshing cylinder = remesh(subdivide(shapes::cylinder(), 3, Scheme::Loop, 0.01, 3), o);
  EXPECT_GT(cylinder.straightenedFolds, 0);
  EXPECT_EQ(cylinder.exactFolds, 0);
  EXPECT_EQ(cylinder.gridMap, "exact");
  EXPECT_EQ(cylinder.cleanupMovedPoints, 0);
  EXPECT_EQ(cylinder.straightenedDefects, -1);  // never cleaned up
  EXPECT_EQ(cylinder.exactDefects, 0);
  EXPECT_EQ(cylinder.flippedTriangles + cylinder.degenerateTriangles + cylinder.selfIntersections,
            0);
  validate(cylinder.mesh, "remeshed");
  startsFromItsFolds(cylinder);

  // The torus's noise's folds left in (unfold.h): taken out, its grids fold 1 and 3.
  RemeshOptions folded = o;
  folded.unfoldInput = false;
  const Remeshing torus = remesh(subdivide(shapes::torus(), 2, Scheme::Loop, 0.02, 7), folded);
  EXPECT_GT(torus.exactFolds, 0);
  EXPECT_GT(torus.straightenedFolds, torus.exactFolds);
  EXPECT_EQ(torus.gridMap, "straightened");
  EXPECT_GT(torus.cleanupMovedPoints, 0);
  startsFromItsFolds(torus);

  const Remeshing smooth = remesh(smoothInput(shapes::icosahedron(), 4, 7), o);
  EXPECT_EQ(smooth.straightenedFolds, 0);
  EXPECT_EQ(smooth.exactFolds, -1);
  EXPECT_EQ(smooth.gridMap, "straightened");
  startsFromItsFolds(smooth);
}

// The grid refined level by level (grid_refinement.h) on the torus above, whose uniform
// grids fold: it folds fewer triangles as sampled, and the clean-up moves fewer points.
TEST(Remesh, RefinesTheGridWhereTheUniformOneFolds) {
  RemeshOptions o;
  o.baseFaces = 20;
  o.levels = 3;
  o.unfoldInput = false;
  o.splitFoldingFaces = false;
  const TriMesh input = subdivide(shapes::torus(), 2, Scheme::Loop, 0.02, 7);
  o.refineGrid = false;
  const Remeshing uniform = remesh(input, o);
  o.refineGrid = true;
  const Remeshing refined = remesh(input, o);
  ASSERT_GT(uniform.straightenedFolds, 0);
  EXPECT_EQ(uniform.gridRefinementMoves, 0);
  EXPECT_GT(refined.gridRefinementMoves, 0);
  EXPECT_LT(refined.straightenedFolds, uniform.straightenedFolds);
  EXPECT_LT(refined.cleanupMovedPoints, uniform.cleanupMovedPoints);
  EXPECT_EQ(refined.flippedTriangles + refined.degenerateTriangles + refined.selfIntersections, 0);
  EXPECT_EQ(topology(refined.mesh), topology(input));
  validate(refined.mesh, "remeshed");
}

TEST(Remesh, SplitsBaseFacesWhereBothGridsFold) {
  // Noisy inputs whose grids fold through both maps: the base faces holding the folds
  // are split (base_flips.h), within 10% of the size asked, and the split base kept
  // only where its grid folds less; without splits the same remesh folds more.
  RemeshOptions o;
  o.levels = 3;
  o.unfoldInput = false;  // the noise's folds left in
  o.refineGrid = false;   // the uniform grids, whose folds these shapes are made for
  int split = 0;
  for (const auto& [input, faces] :
       {std::pair{subdivide(shapes::torus(), 3, Scheme::Loop, 0.025, 3), 150},
        std::pair{subdivide(shapes::slab(2), 3, Scheme::Loop, 0.03, 6), 200}}) {
    SCOPED_TRACE(faces);
    o.baseFaces = faces;
    o.splitFoldingFaces = true;
    const Remeshing with = remesh(input, o);
    o.splitFoldingFaces = false;
    const Remeshing without = remesh(input, o);
    EXPECT_EQ(without.baseSplits, 0);
    EXPECT_LE(with.base.F.rows(), 1.1 * faces);
    EXPECT_EQ(topology(with.mesh), topology(input));
    validate(with.mesh, "remeshed");
    if (with.baseSplits == 0) {  // refused or undone: the remesh without splits
      EXPECT_EQ(with.mesh.V, without.mesh.V);
      continue;
    }
    ++split;
    EXPECT_EQ(with.base.F.rows(), without.base.F.rows() + 2 * with.baseSplits);
    EXPECT_LT(with.straightenedFolds, without.straightenedFolds);
    EXPECT_LT(with.cleanupMovedPoints, without.cleanupMovedPoints);
  }
  EXPECT_GT(split, 0);
}
