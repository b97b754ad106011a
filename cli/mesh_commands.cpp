#include <cstdio>
#include <iostream>

#include "commands.h"
#include "common.h"
#include "osdmra/mesh/io.h"
#include "osdmra/subdivision/shapes.h"
#include "report.h"

namespace osdmra::cli {

int cmdInfo(const Argv& argv) {
  Args args("info", argv, {}, flags());
  args.expectPositional(1, "one input mesh: osdmra info IN");
  const Common opt = common(args);
  const std::string in = args.positional()[0];
  const TriMesh mesh = readValidMesh(in);
  const Connectivity c(mesh.F, static_cast<int>(mesh.V.rows()));
  Json j = topologyJson(mesh, c);
  const auto t0 = Clock::now();
  const Recovery r = recoverSubdivision(mesh.F, static_cast<int>(mesh.V.rows()));
  const double tRecover = seconds(t0);
  const std::string structure = describe(r);
  j.add("levels", r.levels).add("structure", structure);
  if (r.levels > 0) {
    const TriMesh base{Points::Zero(r.numBaseVertices, 3), r.baseFaces, Points()};
    const Connectivity bc(r.baseFaces, r.numBaseVertices);
    j.add("base", topologyJson(base, bc).add("arbitrary_choice", r.arbitraryChoice));
  }
  if (!r.stopReason.empty()) j.add("next_level_fails_because", r.stopReason);
  j.add("recover_seconds", tRecover);
  if (opt.json) {
    std::cout << Json::object().add("file", in).add("mesh", j).str() << "\n";
    return 0;
  }
  const int components = c.numComponents(), loops = c.numBoundaryLoops();
  std::cout << in << ": " << mesh.V.rows() << " vertices, " << mesh.F.rows() << " faces, "
            << c.numEdges() << " edges\n"
            << "  components " << components << ", boundary loops " << loops << ", genus "
            << (2 * components - c.eulerCharacteristic() - loops) / 2 << "\n"
            << "  bounding-box diagonal " << boundingBoxDiagonal(mesh.V) << "\n"
            << "  " << structure << "\n";
  if (r.levels > 0 && !r.stopReason.empty())
    std::cout << "  (one level further down fails: " << r.stopReason << ")\n";
  return 0;
}

int cmdSubdivide(const Argv& argv) {
  Args args("subdivide", argv, {"levels", "scheme", "displace", "seed", "output"}, flags());
  args.expectPositional(1, "one base mesh: osdmra subdivide BASE --levels J -o OUT");
  const Common opt = common(args);
  const std::string in = args.positional()[0], out = args.require("output");
  const int J = static_cast<int>(args.integer("levels", -1, 0, 15));
  if (J < 0) throw Error("subdivide: missing required option --levels");
  const Scheme scheme = parseScheme(args.get("scheme", "loop"));
  const double amplitude = args.real("displace", 0.0, 0.0, 1e6);
  const long long seed = args.integer("seed", 1, 0, (1LL << 62));
  const TriMesh base = readValidMesh(in);
  const auto t0 = Clock::now();
  const TriMesh surface = subdivide(base, J, scheme, amplitude, static_cast<std::uint64_t>(seed));
  writeMesh(out, surface);
  const double t = seconds(t0);
  if (opt.json) {
    std::cout << Json::object()
                     .add("command", "subdivide")
                     .add("input", in)
                     .add("output", out)
                     .add("scheme", schemeName(scheme))
                     .add("levels", J)
                     .add("displace", amplitude)
                     .add("seed", seed)
                     .add("vertices", static_cast<int>(surface.V.rows()))
                     .add("faces", static_cast<int>(surface.F.rows()))
                     .add("seconds", t)
                     .str()
              << "\n";
  } else {
    std::cout << "wrote " << out << ": " << surface.V.rows() << " vertices, " << surface.F.rows()
              << " faces (" << J << " " << schemeName(scheme) << " levels over " << in << ")\n";
  }
  return 0;
}

int cmdShape(const Argv& argv) {
  Args args("shape", argv, {"output"}, flags());
  args.expectPositional(1, "a shape name: osdmra shape NAME -o OUT");
  const std::string out = args.require("output");
  const TriMesh mesh = shapes::byName(args.positional()[0]);
  writeMesh(out, mesh);
  if (args.has("json"))
    std::cout << Json::object()
                     .add("command", "shape")
                     .add("shape", args.positional()[0])
                     .add("output", out)
                     .add("vertices", static_cast<int>(mesh.V.rows()))
                     .add("faces", static_cast<int>(mesh.F.rows()))
                     .str()
              << "\n";
  else
    std::cout << "wrote " << out << ": " << mesh.V.rows() << " vertices, " << mesh.F.rows()
              << " faces\n";
  return 0;
}

int cmdRemesh(const Argv& argv) {
  Args args("remesh", argv, withRemeshOptions({"levels", "output", "samples", "seed"}), flags());
  args.expectPositional(1, "one input mesh: osdmra remesh IN --base-faces N --levels J -o OUT");
  const Common opt = common(args);
  const std::string in = args.positional()[0], out = args.require("output");
  meshFormatForWriting(out);  // refuse a bad output name before the work
  // --remesh is implied: remeshing is this command's work.
  InputOptions input = inputOptions(args);
  input.remesh = true;
  input.remeshing = remeshOptions(args);
  const LoadedSurface s = loadSurface(in, input, opt.progress);
  const RemeshReport& r = *s.remeshing;
  printRemeshWarnings(in, r);
  writeMesh(out, r.result.mesh);
  if (opt.json) {
    std::cout << remeshJson(r).add("command", "remesh").add("input", in).add("output", out).str()
              << "\n";
    return 0;
  }
  if (r.droppedVertices > 0)
    std::printf("%s: dropped %d unreferenced vertices\n", in.c_str(), r.droppedVertices);
  if (r.duplicateFaces > 0)
    std::printf("%s: dropped %d faces that repeat an earlier face's corners\n", in.c_str(),
                r.duplicateFaces);
  if (r.welding.vertices > 0)
    std::printf(
        "%s: welded %d boundary vertices onto others at the same position (%d faces "
        "left with a repeated corner dropped)\n",
        in.c_str(), r.welding.vertices, r.welding.faces);
  if (r.repeatedCornerFaces > 0)
    std::printf("%s: dropped %d faces that name a vertex twice\n", in.c_str(),
                r.repeatedCornerFaces);
  if (r.zippedEdges > 0)
    std::printf("%s: split %d boundary edges at the vertices lying on them (T-junctions)\n",
                in.c_str(), r.zippedEdges);
  const ZeroAreaRepair& z = r.zeroArea;
  if (z.flipped + z.dropped + z.collapsed > 0)
    std::printf("%s: mended %d zero-area faces (%d flipped, %d dropped, %d collapsed)\n",
                in.c_str(), z.flipped + z.dropped + z.collapsed, z.flipped, z.dropped, z.collapsed);
  printRemesh(in, r);
  std::printf("wrote %s\n", out.c_str());
  return 0;
}

}  // namespace osdmra::cli
