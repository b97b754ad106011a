// End-to-end tests of the osdmra command-line tool: round trips through files,
// JSON summaries, and refusals with a clear message, a non-zero exit and no output.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "osdmra/mesh/io.h"
#include "osdmra/pipeline.h"
#include "osdmra/subdivision/shapes.h"
#include "support.h"

namespace fs = std::filesystem;
using namespace osdmra;
using namespace osdmra::test;

namespace {

struct Result {
  int status;
  std::string out, err;
};

// Each test runs the tool in a scratch directory of its own.
class Cli : public testing::Test {
 protected:
  std::string path(const std::string& name) const { return dir_.file(name); }

  Result run(const std::string& args) const {
    const std::string out = path("stdout.txt"), err = path("stderr.txt");
    const std::string cmd = std::string(OSDMRA_CLI) + " " + args + " >" + out + " 2>" + err;
    const int raw = std::system(cmd.c_str());
    Result r{WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, readFile(out), readFile(err)};
    return r;
  }

  // Writes the built-in `shape` to `base`, then, through `subdivide --levels` with
  // `levelsAndOptions` (levels, then scheme, displacement...), its refinement to `out`.
  void makeSurface(const std::string& shape, const std::string& base,
                   const std::string& levelsAndOptions, const std::string& out) const {
    ASSERT_EQ(run("shape " + shape + " -o " + path(base)).status, 0);
    const Result r =
        run("subdivide " + path(base) + " --levels " + levelsAndOptions + " -o " + path(out));
    ASSERT_EQ(r.status, 0) << r.err;
  }

  TempDir dir_;
};

}  // namespace

TEST_F(Cli, SubdivideAnalyzeSynthesizeRoundTrip) {
  for (const char* scheme : {"loop", "linear"}) {
    SCOPED_TRACE(scheme);
    ASSERT_NO_FATAL_FAILURE(makeSurface(
        "genus2", "g2.obj", "3 --scheme " + std::string(scheme) + " --displace 0.05 --seed 11",
        "g2-3.ply"));
    const Result an = run("analyze " + path("g2-3.ply") + " --scheme " + scheme +
                          " --rings 1 --json -o " + path("g2.mra"));
    ASSERT_EQ(an.status, 0) << an.err;
    EXPECT_EQ(an.out.front(), '{');
    EXPECT_NE(an.out.find("\"levels\": 3"), std::string::npos) << an.out;
    EXPECT_NE(an.out.find("\"reconstruction_error\""), std::string::npos);
    const Result syn = run("synthesize " + path("g2.mra") + " -o " + path("back.obj"));
    ASSERT_EQ(syn.status, 0) << syn.err;
    const TriMesh original = readMesh(path("g2-3.ply")), back = readMesh(path("back.obj"));
    ASSERT_EQ(back.V.rows(), original.V.rows());
    EXPECT_TRUE(back.F == original.F);
    EXPECT_LT((back.V - original.V).cwiseAbs().maxCoeff(), 1e-12 * boundingBoxDiagonal(original.V));
    // A coarser level has the base's structure refined fewer times.
    ASSERT_EQ(run("synthesize " + path("g2.mra") + " --level 1 -o " + path("l1.off")).status, 0);
    EXPECT_EQ(readMesh(path("l1.off")).F.rows(), 4 * shapes::slab(2).F.rows());
  }
}

TEST_F(Cli, AnalyzeTakesAnyOrderAndRefusesOtherMeshes) {
  ASSERT_NO_FATAL_FAILURE(makeSurface("octahedron", "oct.obj", "2 --displace 0.05", "oct2.obj"));
  // The base mesh itself has no levels.
  Result r = run("analyze " + path("oct.obj") + " -o " + path("x.mra"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("oct.obj"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no subdivision connectivity"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("x.mra")));
  // More levels than the mesh has: the message says how far down it goes.
  r = run("analyze " + path("oct2.obj") + " --levels 3 -o " + path("x.mra"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("2 levels over a base of 6 vertices and 8 faces"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("3 levels were asked for"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("x.mra")));
  // Vertices and faces in another order, corners rotated: analysed, and written back
  // in the input's own order at full resolution.
  const TriMesh m = readMesh(path("oct2.obj"));
  const TriMesh shuffled = shuffle(m, 37);
  writeMesh(path("shuffled.ply"), shuffled);
  r = run("analyze " + path("shuffled.ply") + " --json -o " + path("s.mra"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"reordered\": true"), std::string::npos) << r.out;
  ASSERT_EQ(run("synthesize " + path("s.mra") + " -o " + path("back.ply")).status, 0);
  const TriMesh back = readMesh(path("back.ply"));
  EXPECT_TRUE(back.F == shuffled.F);
  EXPECT_LT((back.V - shuffled.V).cwiseAbs().maxCoeff(), 1e-12 * boundingBoxDiagonal(m.V));
  r = run("info " + path("shuffled.ply") + " --json");
  EXPECT_NE(r.out.find("\"levels\": 2"), std::string::npos) << r.out;
}

TEST_F(Cli, ClearErrorsForBadArgumentsAndFiles) {
  Result r = run("analyze " + path("missing.obj") + " -o " + path("x.mra"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("missing.obj"), std::string::npos) << r.err;
  r = run("subdivide " + path("missing.obj") + " --levels two -o " + path("x.obj"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("--levels"), std::string::npos) << r.err;
  r = run("info --frobnicate x.obj");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("--frobnicate"), std::string::npos) << r.err;
  r = run("nosuchcommand");
  EXPECT_NE(r.status, 0);
  // A corrupt coefficient file: error, and no output mesh.
  std::ofstream(path("bad.mra")) << "not a coefficient file at all";
  r = run("synthesize " + path("bad.mra") + " -o " + path("out.obj"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("bad.mra"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("out.obj")));
  // A quad mesh names its line.
  std::ofstream(path("quad.obj")) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  r = run("info " + path("quad.obj"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("quad.obj:5"), std::string::npos) << r.err;
}

TEST_F(Cli, InfoFindsLevelsAndTopology) {
  ASSERT_NO_FATAL_FAILURE(makeSurface("cylinder", "cyl.obj", "3", "cyl3.ply"));
  const Result r = run("info " + path("cyl3.ply") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  // The 6 x 3 cylinder is itself a split of a 3 x 2 one, with no extraordinary vertex
  // to pin the choice: one more level, and the report says the base was a choice.
  EXPECT_NE(r.out.find("\"levels\": 4"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"arbitrary_choice\": true"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"boundary_loops\": 2"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"genus\": 0"), std::string::npos) << r.out;
  const Result t = run("info " + std::string(OSDMRA_DATA_DIR) + "/igea-oct6.obj --json");
  ASSERT_EQ(t.status, 0) << t.err;
  EXPECT_NE(t.out.find("\"levels\": 6"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("\"base\": {\"vertices\": 6, \"faces\": 8"), std::string::npos) << t.out;
}

TEST_F(Cli, PolyhedralMaskIsThePapersFigure5) {
  ASSERT_EQ(run("shape valences -o " + path("v.obj")).status, 0);
  // Vertex 10 is the valence-10 apex; at level 1 it keeps valence 10.
  const Result r = run("mask " + path("v.obj") + " --scheme linear --level 1 --vertex 10");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("valence 10"), std::string::npos) << r.out;
  // Centre 10 and ten neighbours of weight 1, after scaling by 6 * 4^j.
  EXPECT_NE(r.out.find("ring 0  vertex     10  "), std::string::npos) << r.out;
  int ones = 0;
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);)
    if (line.find("ring 1") != std::string::npos && line.size() > 2 &&
        line.compare(line.size() - 2, 2, " 1") == 0)
      ++ones;
  EXPECT_EQ(ones, 10) << r.out;
}

TEST_F(Cli, DemoWritesThePapersLevelsOfDetail) {
  const Result r = run("demo --json --samples 2000 --points 5 --out " + path("out"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"reconstruction_error\""), std::string::npos) << r.out;
  for (const char* scheme : {"loop", "linear"})
    for (int budget : {4054, 12310, 16098}) {
      const std::string file =
          path("out/igea-" + std::string(scheme) + "-" + std::to_string(budget) + ".obj");
      const TriMesh m = readValidMesh(file);
      EXPECT_LE(m.F.rows(), budget) << file;
      EXPECT_GT(m.F.rows(), budget * 95 / 100) << file;
    }
  const std::string table = readFile(path("out/errors.md"));
  EXPECT_NE(table.find("| loop | 4054 |"), std::string::npos) << table;
  EXPECT_TRUE(fs::exists(path("out/sweep-loop.csv")));
}

TEST_F(Cli, LodWritesAValidMeshWithinBudgetAndReportsErrors) {
  ASSERT_NO_FATAL_FAILURE(makeSurface("genus2", "g.obj", "3 --displace 0.03", "g3.ply"));
  for (const char* scheme : {"loop", "linear"}) {
    SCOPED_TRACE(scheme);
    const Result r = run("lod " + path("g3.ply") + " --scheme " + scheme +
                         " --budget 1500 --samples 2000 --json -o " + path("lod.obj"));
    ASSERT_EQ(r.status, 0) << r.err;
    const TriMesh m = readValidMesh(path("lod.obj"));
    EXPECT_LE(m.F.rows(), 1500);
    EXPECT_GT(m.F.rows(), 1000);
    EXPECT_EQ(m.N.rows(), std::string(scheme) == "loop" ? m.V.rows() : 0);
    for (const char* key : {"\"triangles\"", "\"coefficients_kept\"", "\"l2_error\"",
                            "\"rms_relative\"", "\"hausdorff_relative\""})
      EXPECT_NE(r.out.find(key), std::string::npos) << key << " in " << r.out;
  }
  // Exactly one of the three ways to truncate.
  const Result bad = run("lod " + path("g3.ply") + " --budget 100 --keep 0.5 -o " + path("x.obj"));
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.err.find("exactly one"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(path("x.obj")));
  // The selection, placement and metric options: each a valid mesh within budget; a
  // fitted mesh has the same faces as the one on the truncated surface, and other
  // vertex positions.
  for (const char* options : {"--selection importance", "--placement fit", "--metric surface",
                              "--selection rd --placement surface --metric domain"}) {
    SCOPED_TRACE(options);
    const Result r =
        run("lod " + path("g3.ply") + " --scheme linear --budget 1500 --samples 2000 " + options +
            " -o " + path("opt.obj"));
    ASSERT_EQ(r.status, 0) << r.err;
    const TriMesh m = readValidMesh(path("opt.obj"));
    EXPECT_LE(m.F.rows(), 1500);
    EXPECT_GT(m.F.rows(), 1000);
  }
  ASSERT_EQ(
      run("lod " + path("g3.ply") +
          " --scheme linear --budget 1500 --samples 2000 --placement surface -o " + path("s.obj"))
          .status,
      0);
  ASSERT_EQ(run("lod " + path("g3.ply") +
                " --scheme linear --budget 1500 --samples 2000 --placement fit -o " + path("f.obj"))
                .status,
            0);
  const TriMesh onSurface = readValidMesh(path("s.obj")), fitted = readValidMesh(path("f.obj"));
  EXPECT_EQ(onSurface.F, fitted.F);
  EXPECT_GT((onSurface.V - fitted.V).cwiseAbs().maxCoeff(), 1e-9);
  for (const char* option : {"--selection best", "--placement quadric", "--metric area"}) {
    const Result r =
        run("lod " + path("g3.ply") + " --budget 100 " + option + " -o " + path("x.obj"));
    EXPECT_EQ(r.status, 1) << option;
    EXPECT_NE(r.err.find("must be"), std::string::npos) << r.err;
  }
}

// lod's defaults are the polyhedral scheme and the closest fit (kLodDefaults: the
// closest levels of detail to the input mesh, docs/LOD.md); a budget below the base
// mesh still gives the base, with a warning that says so.
TEST_F(Cli, LodDefaultsAndABudgetBelowTheBase) {
  ASSERT_NO_FATAL_FAILURE(makeSurface("genus2", "g.obj", "3 --displace 0.03", "g3.ply"));
  const Result r =
      run("lod " + path("g3.ply") + " --budget 1500 --samples 2000 --json -o " + path("d.obj"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"scheme\": \"linear\""), std::string::npos) << r.out;
  ASSERT_EQ(
      run("lod " + path("g3.ply") +
          " --budget 1500 --samples 2000 --scheme linear --placement closest -o " + path("c.obj"))
          .status,
      0);
  const TriMesh byDefault = readValidMesh(path("d.obj")), closest = readValidMesh(path("c.obj"));
  EXPECT_EQ(byDefault.F, closest.F);
  EXPECT_EQ(byDefault.V, closest.V);
  const int baseFaces = static_cast<int>(readValidMesh(path("g.obj")).F.rows());
  const Result under = run("lod " + path("g3.ply") + " --budget " + std::to_string(baseFaces - 1) +
                           " --samples 2000 --json -o " + path("u.obj"));
  ASSERT_EQ(under.status, 0) << under.err;
  EXPECT_EQ(readValidMesh(path("u.obj")).F.rows(), baseFaces);
  EXPECT_NE(under.err.find("warning: " + path("g3.ply") + ": the base mesh has " +
                           std::to_string(baseFaces) + " triangles, more than the budget"),
            std::string::npos)
      << under.err;
  EXPECT_NE(under.out.find("\"warnings\": [\"the base mesh has"), std::string::npos) << under.out;
}

TEST_F(Cli, SweepWritesCsvAndPlot) {
  ASSERT_NO_FATAL_FAILURE(makeSurface("octahedron", "o.obj", "3 --displace 0.03", "o3.obj"));
  const bool gnuplot = std::system("command -v gnuplot >/dev/null 2>&1") == 0;
  const std::string plot = gnuplot ? " --plot " + path("s.png") : "";
  const Result r =
      run("sweep " + path("o3.obj") + " --points 6 --samples 1000 --csv " + path("s.csv") + plot);
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream csv(readFile(path("s.csv")));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("triangles,coefficients_kept", 0), 0u) << line;
  int rows = 0, previousTriangles = 0;
  while (std::getline(csv, line)) {
    const int t = std::stoi(line.substr(0, line.find(',')));
    EXPECT_GE(t, previousTriangles);
    previousTriangles = t;
    ++rows;
  }
  EXPECT_EQ(rows, 6);
  EXPECT_EQ(previousTriangles, 8 * 64);  // the last row keeps everything
  if (gnuplot) {
    const std::string png = readFile(path("s.png"));
    ASSERT_GT(png.size(), 1000u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
  }
}

TEST_F(Cli, RemeshAnyMeshAndCutNonManifoldEdges) {
  ASSERT_NO_FATAL_FAILURE(makeSurface("torus", "t.obj", "3 --displace 0.02", "t3.obj"));
  // An unreferenced vertex is dropped, not refused; so is a copy of a face (written
  // the other way round), which another tool's output made a non-manifold edge of.
  { std::ofstream(path("t3.obj"), std::ios::app) << "v 9 9 9\n"; }
  {
    const TriMesh t = readMesh(path("t3.obj"));
    std::ofstream(path("t3dup.obj")) << readFile(path("t3.obj")) << "f " << t.F(7, 2) + 1 << " "
                                     << t.F(7, 1) + 1 << " " << t.F(7, 0) + 1 << "\n";
    const Result dup =
        run("remesh " + path("t3dup.obj") +
            " --samples 2000 --base-faces 100 --levels 2 --json -o " + path("dup.obj"));
    ASSERT_EQ(dup.status, 0) << dup.err;
    EXPECT_NE(dup.out.find("\"duplicate_faces_dropped\": 1"), std::string::npos) << dup.out;
  }
  const Result r = run("remesh " + path("t3.obj") +
                       " --samples 2000 --base-faces 100 --levels 4 --json -o " + path("r.ply"));
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* key :
       {"\"base_faces\"", "\"rms_relative\"", "\"hausdorff_relative\"",
        "\"unreferenced_vertices_dropped\": 1", "\"flipped_triangles\": 0",
        "\"degenerate_triangles\": 0", "\"self_intersections\": 0", "\"warnings\": []",
        "\"feature_edges_dropped\": 0", "\"input_folds\": {\"corners\": "})
    EXPECT_NE(r.out.find(key), std::string::npos) << key << " in " << r.out;
  // The map kept left nothing. Since the parameterisation is smoothed (smoothing.h) the
  // straightened map leaves 14-21 defects on this noisy torus at J = 4 (none before), and
  // the exact inverse, which the smoothing does not change, is kept instead.
  EXPECT_TRUE(
      (r.out.find("\"grid_map\": {\"used\": \"straightened\", ") != std::string::npos &&
       r.out.find("\"straightened_defects\": 0, \"exact_defects\": -1}") != std::string::npos) ||
      (r.out.find("\"used\": \"exact\"") != std::string::npos &&
       r.out.find("\"exact_defects\": 0}") != std::string::npos))
      << r.out;
  // The stages relaxed vertex by vertex (the default, --stages auto) left nothing here
  // either, so that remesh was kept and the mesh-wide one never made.
  EXPECT_NE(r.out.find("\"stages\": \"vertex\", \"per_vertex_defects\": 0}"), std::string::npos)
      << r.out;
  // Without the smoothing (--smoothing-sweeps 0) the straightened map alone is clean
  // there, as it was before the smoothing; a negative count is refused, by its flag.
  const Result unsmoothed =
      run("remesh " + path("t3.obj") +
          " --samples 2000 --base-faces 100 --levels 4 --smoothing-sweeps 0 --json -o " +
          path("u.ply"));
  ASSERT_EQ(unsmoothed.status, 0) << unsmoothed.err;
  // The JSON says what the smoothing did: some moves by default, none without it.
  EXPECT_EQ(r.out.find("\"smoothing\": {\"moves\": 0,"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"smoothing\": {\"moves\": "), std::string::npos) << r.out;
  EXPECT_NE(unsmoothed.out.find("\"smoothing\": {\"moves\": 0, \"refused\": 0}"), std::string::npos)
      << unsmoothed.out;
  // The JSON says which map the grid was sampled through, how many grid triangles each
  // folded as sampled, and what each left after the clean-up (-1: not sampled, not
  // cleaned up).
  EXPECT_NE(unsmoothed.out.find("\"grid_map\": {\"used\": \"straightened\", "
                                "\"straightened_folds\": "),
            std::string::npos)
      << unsmoothed.out;
  EXPECT_NE(unsmoothed.out.find("\"straightened_defects\": 0, \"exact_defects\": -1}"),
            std::string::npos)
      << unsmoothed.out;
  EXPECT_NE(unsmoothed.out.find("\"base_splits\": {\"made\": 0, \"refused\": 0, \"at_points\": 0}"),
            std::string::npos)
      << unsmoothed.out;
  // An option out of its range is refused, naming the option, and nothing is written.
  auto rejects = [&](const std::string& option, const std::string& message) {
    SCOPED_TRACE(option);
    const Result bad = run("remesh " + path("t3.obj") + " " + option + " -o " + path("n.ply"));
    EXPECT_NE(bad.status, 0);
    EXPECT_NE(bad.err.find(message), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(path("n.ply")));
  };
  rejects("--smoothing-sweeps -1", "--smoothing-sweeps");
  // --stages takes auto, vertex or mesh, and names what it got otherwise.
  rejects("--stages edge", "--stages: expected auto, vertex or mesh, got 'edge'");
  rejects("--retriangulation fan", "--retriangulation: expected shape or error, got 'fan'");
  rejects("--base-splits yes", "--base-splits: expected on or off, got 'yes'");
  rejects("--grid-refinement no", "--grid-refinement: expected on or off, got 'no'");
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  // The same surface as a triangle soup (every face with its own three vertices, as an
  // STL file turned into OBJ) is welded first, and remeshes without defects.
  {
    const TriMesh t = readMesh(path("t3.obj"));
    std::ofstream soup(path("soup.obj"));
    soup.precision(17);
    for (Eigen::Index f = 0; f < t.F.rows(); ++f)
      for (int k = 0; k < 3; ++k)
        soup << "v " << t.V(t.F(f, k), 0) << " " << t.V(t.F(f, k), 1) << " " << t.V(t.F(f, k), 2)
             << "\n";
    for (Eigen::Index f = 0; f < t.F.rows(); ++f)
      soup << "f " << 3 * f + 1 << " " << 3 * f + 2 << " " << 3 * f + 3 << "\n";
  }
  const Result s = run("remesh " + path("soup.obj") +
                       " --samples 2000 --base-faces 100 --levels 4 --json -o " + path("s.ply"));
  ASSERT_EQ(s.status, 0) << s.err;
  for (const char* key : {"\"welded_vertices\": ", "\"self_intersections\": 0", "\"warnings\": []"})
    EXPECT_NE(s.out.find(key), std::string::npos) << key << " in " << s.out;
  EXPECT_EQ(s.out.find("\"welded_vertices\": 0"), std::string::npos) << s.out;
  // A base far too coarse, split once: the result is far from the input somewhere,
  // and the user is told (stderr and JSON) but still gets it.
  const Result coarse = run("remesh " + path("t3.obj") +
                            " --samples 2000 --base-faces 4 --levels 1 --json -o " + path("c.obj"));
  ASSERT_EQ(coarse.status, 0) << coarse.err;
  EXPECT_NE(coarse.err.find("warning: " + path("t3.obj") + ": the remeshed surface is"),
            std::string::npos)
      << coarse.err;
  // (It also keeps more base faces than the 4 asked for: a torus needs more.) Both
  // warnings are in the JSON's list.
  const std::size_t list = coarse.out.find("\"warnings\": [");
  ASSERT_NE(list, std::string::npos) << coarse.out;
  EXPECT_NE(coarse.out.find("\"the base has", list), std::string::npos) << coarse.out;
  EXPECT_NE(coarse.out.find("faces, more than the 4 asked for", list), std::string::npos)
      << coarse.out;
  EXPECT_NE(coarse.out.find("\"the remeshed surface is", list), std::string::npos) << coarse.out;
  EXPECT_TRUE(fs::exists(path("c.obj")));
  // --max-faces splits that larger base fewer times than --levels asks.
  const Result capped =
      run("remesh " + path("t3.obj") +
          " --samples 2000 --base-faces 4 --levels 5 --max-faces 2000 --json -o " + path("c.obj"));
  ASSERT_EQ(capped.status, 0) << capped.err;
  EXPECT_EQ(capped.out.find("\"levels\": 5,"), std::string::npos) << capped.out;
  EXPECT_LE(readValidMesh(path("c.obj")).F.rows(), 2000);
  const TriMesh m = readValidMesh(path("r.ply"));
  EXPECT_EQ(m.F.rows() % 16, 0);
  // lod through --remesh reports the remeshing apart, and the level of detail's
  // distances to the input as given.
  const Result lod = run("lod " + path("t3.obj") +
                         " --remesh --base-faces 100 --levels 2 --budget 600 --samples 2000 "
                         "--json -o " +
                         path("l.obj"));
  ASSERT_EQ(lod.status, 0) << lod.err;
  EXPECT_NE(lod.out.find("\"remesh\": {"), std::string::npos) << lod.out;
  EXPECT_NE(lod.out.find("\"to_input\": {\"rms_relative\": "), std::string::npos) << lod.out;
  // Without --base-faces, a budget remeshes over the budget, a half, a quarter and a
  // sixteenth of it, so that a small budget can be met (a base of the default 300 faces
  // could not), cuts the input's own hierarchy where it has one, and keeps the closest:
  // every trial reported, one kept.
  const Result small =
      run("lod " + path("t3.obj") + " --remesh --levels 2 --budget 200 --samples 2000 --json -o " +
          path("l.obj"));
  ASSERT_EQ(small.status, 0) << small.err;
  const std::size_t trials = small.out.find("\"base_trials\": [{\"base_faces_asked\": 200,");
  ASSERT_NE(trials, std::string::npos) << small.out;
  EXPECT_NE(small.out.find("{\"base_faces_asked\": 100,", trials), std::string::npos) << small.out;
  EXPECT_NE(small.out.find("{\"base_faces_asked\": 50,", trials), std::string::npos) << small.out;
  EXPECT_NE(small.out.find("{\"base_faces_asked\": 12,", trials), std::string::npos) << small.out;
  // The whole budget again, with skinny faces where flat (BudgetSearchOptions::skinnyWhereFlat),
  // a third time with those and its edges flipped towards the input (flipTowardsInput),
  // and a fourth and a fifth with their removals in order of error (orderByError).
  EXPECT_NE(small.out.find("\"skinny_where_flat\": 0.1,", trials), std::string::npos) << small.out;
  EXPECT_NE(small.out.find("\"flips_towards_input\": ", trials), std::string::npos) << small.out;
  EXPECT_NE(small.out.find("\"order_by_error\": true,", trials), std::string::npos) << small.out;
  EXPECT_NE(small.out.find("\"crossing_pairs\": 0, \"rms_relative\": ", trials), std::string::npos)
      << small.out;
  // The torus has subdivision connectivity (3 levels over 48 faces): its own hierarchy is
  // one more trial, the remeshings the others.
  EXPECT_NE(small.out.find("{\"base_faces_asked\": 0, \"base_faces\": 48, \"levels\": 3,", trials),
            std::string::npos)
      << small.out;
  EXPECT_NE(small.out.find("\"input_hierarchy\": true, \"kept\": ", trials), std::string::npos)
      << small.out;
  EXPECT_NE(small.out.find("\"input_hierarchy\": false, \"kept\": ", trials), std::string::npos)
      << small.out;
  const std::size_t kept = small.out.find("\"kept\": true", trials);
  ASSERT_NE(kept, std::string::npos) << small.out;
  EXPECT_EQ(small.out.find("\"kept\": true", kept + 1), std::string::npos) << small.out;
  EXPECT_LE(readValidMesh(path("l.obj")).F.rows(), 200);
  EXPECT_NE(small.out.find("\"warnings\": []"), std::string::npos) << small.out;
  // --skinny-where-flat 0: no trial over the whole budget with skinny faces; a fraction
  // outside [0, 1] is refused, naming the option.
  const Result fat = run("lod " + path("t3.obj") +
                         " --remesh --levels 2 --budget 200 --samples 2000 --skinny-where-flat 0 "
                         "--json -o " +
                         path("l.obj"));
  ASSERT_EQ(fat.status, 0) << fat.err;
  EXPECT_NE(fat.out.find("\"base_trials\": [{\"base_faces_asked\": 200,"), std::string::npos);
  EXPECT_EQ(fat.out.find("\"skinny_where_flat\": 0.1"), std::string::npos) << fat.out;
  const Result badFraction =
      run("remesh " + path("t3.obj") + " --skinny-where-flat 2 -o " + path("r.obj"));
  EXPECT_NE(badFraction.status, 0);
  EXPECT_NE(badFraction.err.find("skinny-where-flat"), std::string::npos) << badFraction.err;
  // Without --levels too, each base gets as many levels as keep its remeshing within
  // --max-faces (2^19 by default, the remesher's 5 levels over 300 faces; 5 over 50),
  // counted on the base the remesher made: within 3,200, 3 over 50, and 3 over the 30
  // faces the torus keeps for the 12 asked (12 * 4^4 would fit; lod's stages per vertex
  // and retriangulation by error keep 30 since the input's folds are taken out first,
  // unfold.h: 44 before).
  const Result levels = run("lod " + path("t3.obj") + " --remesh --budget 200 --max-faces 3200 " +
                            "--samples 500 --json -o " + path("l.obj"));
  ASSERT_EQ(levels.status, 0) << levels.err;
  EXPECT_NE(levels.out.find("{\"base_faces_asked\": 50, \"base_faces\": 50, \"levels\": 3,"),
            std::string::npos)
      << levels.out;
  EXPECT_NE(levels.out.find("{\"base_faces_asked\": 12, \"base_faces\": 30, \"levels\": 3,"),
            std::string::npos)
      << levels.out;
  // A torus cannot be remeshed over the 8 or 4 faces a budget of 8 asks for: the
  // level of detail is the base the remesher made (the same faces for either, the
  // larger ask kept on the tie), over the budget, and a warning says why.
  const Result tiny = run("lod " + path("t3.obj") +
                          " --remesh --levels 1 --budget 8 --samples 500 -o " + path("l.obj"));
  ASSERT_EQ(tiny.status, 0) << tiny.err;
  EXPECT_GT(readValidMesh(path("l.obj")).F.rows(), 8);
  EXPECT_NE(tiny.err.find("more than the budget 8, and no level of detail is coarser (the "
                          "remesher kept more base faces than the 8 asked for"),
            std::string::npos)
      << tiny.err;
  // So does the demo, on any mesh.
  const Result demo =
      run("demo " + path("t3.obj") +
          " --remesh --base-faces 100 --levels 2 --points 3 --samples 500 --out " + path("demo"));
  ASSERT_EQ(demo.status, 0) << demo.err;
  EXPECT_NE(readFile(path("demo/errors.md")).find("Remeshing"), std::string::npos);
  EXPECT_TRUE(fs::exists(path("demo/t3-loop-4054.obj")));
  // Two tetrahedra sharing one vertex: a bowtie, split into one vertex per tetrahedron
  // and remeshed; where they touch, the input's own crossing pairs are said.
  {
    std::ofstream f(path("bowtie.obj"));
    f << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv -1 0 0\nv 0 -1 0\nv 0 0 -1\n"
         "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
         "f 1 6 5\nf 1 5 7\nf 1 7 6\nf 5 6 7\n";
  }
  const Result split =
      run("remesh " + path("bowtie.obj") + " --samples 2000 --base-faces 8 --levels 2 --json -o " +
          path("bow.obj"));
  ASSERT_EQ(split.status, 0) << split.err;
  EXPECT_NE(split.out.find("\"split_vertices\": 1"), std::string::npos) << split.out;
  EXPECT_NE(split.err.find("(the input itself has 6 crossing pairs)"), std::string::npos)
      << split.err;
  // Three sheets on one edge: a command that takes the mesh as it is refuses it, naming
  // the edge; the remesher cuts the edge open (one sheet per page) and says so.
  {
    std::ofstream f(path("book.obj"));
    f << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 1 1 0\nv 1 -1 0\nv 1 0 1\n"
         "f 1 2 3\nf 2 6 3\nf 2 1 4\nf 2 4 7\nf 1 2 5\nf 2 8 5\n";
  }
  const Result bad = run("analyze " + path("book.obj") + " -o " + path("b.mra"));
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.err.find("edge (0, 1) is shared by 3 faces"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(path("b.mra")));
  const Result cut = run("remesh " + path("book.obj") +
                         " --samples 2000 --base-faces 8 --levels 2 --json -o " + path("b.obj"));
  ASSERT_EQ(cut.status, 0) << cut.err;
  EXPECT_NE(cut.out.find("\"non_manifold_edges_cut\": 1"), std::string::npos) << cut.out;
  EXPECT_NE(cut.err.find("1 non-manifold edges (three faces or more) were cut open"),
            std::string::npos)
      << cut.err;
  EXPECT_EQ(topology(readValidMesh(path("b.obj"))).components, 3);
  // A CAD export's zero-area faces are mended, and the command says so.
  writeMesh(path("fanned.off"), fannedCube(4));
  const Result fanned = run("remesh " + path("fanned.off") +
                            " --samples 2000 --base-faces 30 --levels 2 -o " + path("f.obj"));
  ASSERT_EQ(fanned.status, 0) << fanned.err;
  EXPECT_NE(fanned.out.find("mended 12 zero-area faces (12 flipped"), std::string::npos)
      << fanned.out;
}

// ---- compress / decompress ---------------------------------------------------------

namespace {

// The number after "key": in a one-line JSON object (NaN when absent).
double jsonNumber(const std::string& json, const std::string& key) {
  const std::size_t at = json.find("\"" + key + "\": ");
  if (at == std::string::npos) return std::nan("");
  return std::stod(json.substr(at + key.size() + 4));
}

}  // namespace

TEST_F(Cli, CompressMeetsEachRateTargetWithinFivePercent) {
  ASSERT_NO_FATAL_FAILURE(
      makeSurface("icosahedron", "ico.obj", "4 --displace 0.01 --seed 3", "ico4.obj"));
  const TriMesh input = readMesh(path("ico4.obj"));
  const double vertices = static_cast<double>(input.V.rows());
  AnalysisOptions structureOnly;
  structureOnly.approximator = false;
  const AnalysedSurface canonical(input, structureOnly);
  struct Target {
    std::string flag;
    double value;
    std::string text;
  };
  for (const Target& t : {Target{"--bytes", 1000, "1000"}, Target{"--bits-per-vertex", 1.5, "1.5"},
                          Target{"--psnr", 50, "50"}, Target{"--psnr", 70, "70"}}) {
    SCOPED_TRACE(t.flag + " " + t.text);
    // 5,000 samples a side for the surface PSNR: a quicker search, the same check.
    const Result c = run("compress " + path("ico4.obj") + " " + t.flag + " " + t.text +
                         " --samples 5000 --json -o " + path("ico.osz"));
    ASSERT_EQ(c.status, 0) << c.err;
    const double bytes = jsonNumber(c.out, "bytes"), dB = jsonNumber(c.out, "psnr");
    EXPECT_EQ(bytes, static_cast<double>(fs::file_size(path("ico.osz"))));
    EXPECT_NEAR(jsonNumber(c.out, "bits_per_vertex"), 8 * bytes / vertices, 1e-9);
    if (t.flag == "--bytes") {
      EXPECT_LE(bytes, t.value);
      EXPECT_GE(bytes, 0.95 * t.value);
    } else if (t.flag == "--bits-per-vertex") {
      EXPECT_LE(8 * bytes / vertices, t.value);
      EXPECT_GE(8 * bytes / vertices, 0.95 * t.value);
    } else {
      EXPECT_GE(dB, t.value);
      EXPECT_LE(dB, 1.05 * t.value);
    }
    // The decoder gets the PSNR the encoder reported, measured here independently.
    // The codec keeps no vertex order of its own: it writes the canonical order of the
    // structure it recovered (hierarchy.h), which the pipeline recovers here too.
    const Result d = run("decompress " + path("ico.osz") + " --json -o " + path("back.obj"));
    ASSERT_EQ(d.status, 0) << d.err;
    const TriMesh back = readMesh(path("back.obj"));
    ASSERT_EQ(back.V.rows(), input.V.rows());
    ASSERT_TRUE(back.F == canonical.hierarchy().faces(4));
    const Points& original = canonical.canonicalPositions();
    const double rms = std::sqrt((back.V - original).rowwise().squaredNorm().mean());
    EXPECT_NEAR(20 * std::log10(boundingBoxDiagonal(original) / rms),
                jsonNumber(c.out, "psnr_vertices"), 1e-6);
  }
}

TEST_F(Cli, DecompressDecodesAPrefixAndRefusesOtherFiles) {
  ASSERT_NO_FATAL_FAILURE(makeSurface("octahedron", "oct.obj", "4 --displace 0.02", "oct4.obj"));
  ASSERT_EQ(run("compress " + path("oct4.obj") + " --samples 2000 -o " + path("oct.osz")).status,
            0);
  const double whole = static_cast<double>(fs::file_size(path("oct.osz")));
  const Result d = run("decompress " + path("oct.osz") + " --bytes 400 --json -o " + path("p.obj"));
  ASSERT_EQ(d.status, 0) << d.err;
  EXPECT_EQ(jsonNumber(d.out, "bytes"), 400);
  EXPECT_EQ(jsonNumber(d.out, "file_bytes"), whole);
  EXPECT_NE(d.out.find("\"cut\": true"), std::string::npos) << d.out;
  EXPECT_EQ(readMesh(path("p.obj")).F.rows(), 8 * 256);
  // Not a .osz file, or too short to hold the header: a message, exit 1, no output.
  for (const std::string& bad : {std::string("oct4.obj"), std::string("oct.osz --bytes 30")}) {
    const Result r = run("decompress " + path(bad) + " -o " + path("bad.obj"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("osdmra: "), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("bad.obj")));
  }
  const Result both =
      run("compress " + path("oct4.obj") + " --psnr 60 --bytes 900 -o " + path("x.osz"));
  EXPECT_EQ(both.status, 1);
  EXPECT_NE(both.err.find("at most one of"), std::string::npos) << both.err;
}

// compress codes with fixed wavelets unless asked otherwise (--rings asks for
// quasi-wavelets), and the decoder reports what the stream holds.
TEST_F(Cli, CompressDefaultsToFixedWavelets) {
  ASSERT_NO_FATAL_FAILURE(makeSurface("octahedron", "oct.obj", "3 --displace 0.02", "oct3.obj"));
  for (const auto& [flags, kind] : {std::pair<std::string, std::string>{"", "fixed"},
                                    {"--rings 2", "quasi"},
                                    {"--wavelets lazy", "lazy"},
                                    {"--wavelets quasi", "quasi"}}) {
    SCOPED_TRACE(flags);
    const Result c = run("compress " + path("oct3.obj") + " " + flags +
                         " --samples 2000 --json -o " + path("o.osz"));
    ASSERT_EQ(c.status, 0) << c.err;
    EXPECT_NE(c.out.find("\"wavelets\": \"" + kind + "\""), std::string::npos) << c.out;
    const Result d = run("decompress " + path("o.osz") + " --json -o " + path("o.obj"));
    ASSERT_EQ(d.status, 0) << d.err;
    EXPECT_NE(d.out.find("\"wavelets\": \"" + kind + "\""), std::string::npos) << d.out;
  }
}

TEST_F(Cli, CompressRemeshesAnyManifoldMeshAndRefusesWithoutIt) {
  // With --remesh any manifold mesh goes through the remesher first (here a displaced
  // torus, remeshed over a base of about 100 faces), and the stream decodes to a mesh
  // over the remesher's base with the input's topology.
  ASSERT_NO_FATAL_FAILURE(makeSurface("torus", "t.obj", "3 --displace 0.02", "t3.obj"));
  const Result c =
      run("compress " + path("t3.obj") +
          " --remesh --base-faces 100 --levels 3 --bytes 3000 --samples 2000 --json -o " +
          path("t.osz"));
  ASSERT_EQ(c.status, 0) << c.err;
  EXPECT_NE(c.out.find("\"remesh\": {"), std::string::npos) << c.out;
  const double bytes = jsonNumber(c.out, "bytes"), baseFaces = jsonNumber(c.out, "base_faces");
  EXPECT_EQ(bytes, static_cast<double>(fs::file_size(path("t.osz"))));
  EXPECT_LE(bytes, 3000);
  EXPECT_GE(bytes, 0.95 * 3000);
  const Result d = run("decompress " + path("t.osz") + " --json -o " + path("back.obj"));
  ASSERT_EQ(d.status, 0) << d.err;
  const TriMesh back = readValidMesh(path("back.obj"));
  EXPECT_EQ(static_cast<double>(back.F.rows()), baseFaces * 64);
  EXPECT_EQ(topology(back), topology(readMesh(path("t3.obj"))));
  // Six faces are no subdivision of anything: without --remesh, a message and no file.
  {
    std::ofstream f(path("six.obj"));
    f << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1 1 1\n"
         "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 5\nf 2 5 4\nf 3 4 5\n";
  }
  const Result bad = run("compress " + path("six.obj") + " -o " + path("six.osz"));
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.err.find("no subdivision connectivity"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(path("six.osz")));
}
