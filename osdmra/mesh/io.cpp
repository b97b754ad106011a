// Mesh I/O dispatch: the format from the file name, then one reader or writer per
// format (obj.cpp, off.cpp, ply.cpp). Files are written atomically (base/file.h).
#include "osdmra/mesh/io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <system_error>

#include "osdmra/base/file.h"
#include "osdmra/mesh/detail/out_buffer.h"
#include "osdmra/mesh/detail/text.h"

namespace osdmra {

using detail::fail;

namespace {
const std::string kNoStl =
    "osdmra does not write STL (a soup of float triangles loses the mesh's vertices and "
    "precision); write .obj, .off or .ply";
}  // namespace

MeshFormat meshFormatFromPath(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".off") return MeshFormat::Off;
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".stl") return MeshFormat::Stl;
  fail(path + ": unknown mesh format " + (ext.empty() ? "(no extension)" : detail::quote(ext)) +
       "; expected .obj, .off, .ply or .stl");
}

MeshFormat meshFormatForWriting(const std::string& path) {
  const MeshFormat format = meshFormatFromPath(path);
  if (format == MeshFormat::Stl) fail(path + ": " + kNoStl);
  return format;
}

TriMesh readMesh(std::istream& in, MeshFormat format, const std::string& source,
                 const ReadOptions& options) {
  switch (format) {
    case MeshFormat::Obj:
      return readObj(in, source, options);
    case MeshFormat::Off:
      return readOff(in, source, options);
    case MeshFormat::Ply:
      return readPly(in, source, options);
    case MeshFormat::Stl:
      return readStl(in, source, options);
  }
  fail(source + ": unknown mesh format");
}

TriMesh readMesh(const std::string& path, const ReadOptions& options) {
  const MeshFormat format = meshFormatFromPath(path);
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) fail(path + ": is a directory, not a mesh file");
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path + ": cannot open: " + (errno ? std::strerror(errno) : "unknown error"));
  try {
    return readMesh(in, format, path, options);
  } catch (const Error& e) {
    // LineReader reports bare "read error"s; give them the file.
    if (std::string_view(e.what()).rfind(path, 0) == 0) throw;
    throw Error(path + ": " + e.what());
  }
}

TriMesh readValidMesh(const std::string& path) {
  TriMesh mesh = readMesh(path);
  validate(mesh, path);
  return mesh;
}

void writeMesh(std::ostream& out, MeshFormat format, const TriMesh& mesh,
               const WriteOptions& opts) {
  switch (format) {
    case MeshFormat::Obj:
      return writeObj(out, mesh, opts);
    case MeshFormat::Off:
      return writeOff(out, mesh, opts);
    case MeshFormat::Ply:
      return writePly(out, mesh, opts);
    case MeshFormat::Stl:
      fail(kNoStl);
  }
}

void writeMesh(const std::string& path, const TriMesh& mesh, const WriteOptions& opts) {
  const MeshFormat format = meshFormatForWriting(path);  // before touching any file
  try {
    detail::checkWritable(mesh);  // before touching the file system
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
  writeFileAtomically(path, [&](std::ostream& out) { writeMesh(out, format, mesh, opts); });
}

}  // namespace osdmra
