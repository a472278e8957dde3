#include "fuzz_targets.h"

#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "mesh_checks.h"
#include "mesh_io.h"

namespace tb::fuzz {
namespace fs = std::filesystem;

Workspace::Workspace(const std::string& aux_dir) {
  static std::atomic<int> count{0};
  dir_ =
      (fs::temp_directory_path() / ("tb-fuzz-" + std::to_string(::getpid()) + "-" + std::to_string(count.fetch_add(1))))
          .string();
  fs::remove_all(dir_);
  fs::create_directories(dir_);
  if (!aux_dir.empty()) fs::copy(aux_dir, dir_, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
}

Workspace::~Workspace() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

std::string Workspace::path(const std::string& name) const { return (fs::path(dir_) / name).string(); }

std::string Workspace::write(const std::string& name, const std::string& bytes) const {
  const std::string p = path(name);
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw std::logic_error("fuzz workspace: cannot write " + p);
  return p;
}

namespace {

/// A surface reader, then the checks the runner makes on every surface it reads
/// (experiments/mesh_recipe.cc build_mesh).
Target surface_target(const std::string& name, const std::string& extension, const std::string& description) {
  const std::string file = "input." + extension;
  return {name,
          description,
          [file](const std::string& bytes, const Workspace& w) {
            const std::string p = w.write(file, bytes);
            SurfaceMesh m = read_surface(p);
            check_and_orient_surface(p, m);
          },
          {file},
          {}};
}

/// A volume reader; read_volume checks the tets itself (orient_and_check_tets).
Target volume_target(const std::string& name, const std::string& extension, const std::string& description) {
  const std::string file = "input." + extension;
  return {name,
          description,
          [file](const std::string& bytes, const Workspace& w) { read_volume(w.write(file, bytes)); },
          {file},
          {}};
}

}  // namespace

std::vector<Target> mesh_targets() {
  std::vector<Target> t;
  t.push_back(surface_target("obj", "obj", "Wavefront OBJ surface (read_surface, then check_and_orient_surface)"));
  t.push_back(surface_target("off", "off", "OFF surface"));
  t.push_back(surface_target("stl_ascii", "stl", "ASCII STL surface"));
  t.push_back(surface_target("stl_binary", "stl", "binary STL surface (same reader, binary seeds)"));
  t.push_back(surface_target("ply_ascii", "ply", "PLY surface, ascii"));
  t.push_back(surface_target("ply_binary", "ply", "PLY surface, binary little and big endian"));
  t.push_back(surface_target("vtu_surface", "vtu", "VTU triangle surface (read_vtu_cells)"));
  t.push_back(volume_target("gmsh", "msh", "Gmsh .msh volume, versions 1, 2 and 4.1 ASCII (read_volume)"));
  t.push_back(
      {"tetgen",
       "TetGen .node + .ele volume (read_volume); the input is the .node text, a '#--ele--' line, the .ele text",
       [](const std::string& bytes, const Workspace& w) {
         const size_t cut = bytes.find(kTetgenSeparator);
         w.write("input.node", bytes.substr(0, cut));
         w.write("input.ele", cut == std::string::npos ? std::string() : bytes.substr(cut + 1));
         read_volume(w.path("input.ele"));
       },
       {"input.node", "input.ele"},
       {}});
  t.push_back({"tetgen_face",
               "TetGen .face triangles (read_tetgen_faces, first index 1)",
               [](const std::string& bytes, const Workspace& w) { read_tetgen_faces(w.write("input.face", bytes), 1); },
               {"input.face"},
               {}});
  t.push_back(volume_target("vtu_volume", "vtu", "VTU tetrahedral volume (read_vtu_cells)"));
  // The keywords each format's reader reacts to.
  const std::vector<std::string> obj = {"v ", "f ", "vt ", "vn ", "/", "//", "# ", "g ", "o ", "s off", "usemtl "};
  const std::vector<std::string> off = {"OFF", "COFF", "NOFF", "OFF ", "4 ", "3 ", "# "};
  const std::vector<std::string> stl = {"solid",
                                        "endsolid",
                                        "facet normal",
                                        "outer loop",
                                        "vertex",
                                        "endloop",
                                        "endfacet",
                                        std::string(4, '\0'),
                                        "\xff\xff\xff\xff",
                                        std::string("\x00\x00\x80\x7f", 4),
                                        std::string("\x00\x00\xc0\x7f", 4)};
  const std::vector<std::string> ply = {"ply",
                                        "format ascii 1.0",
                                        "format binary_little_endian 1.0",
                                        "format binary_big_endian 1.0",
                                        "element vertex ",
                                        "element face ",
                                        "property float x",
                                        "property double y",
                                        "property list uchar int vertex_indices",
                                        "property list uint8 uint32 vertex_index",
                                        "end_header",
                                        "comment",
                                        "element edge 3"};
  const std::vector<std::string> vtu = {"<VTKFile type=\"UnstructuredGrid\">",
                                        "<Points>",
                                        "</Points>",
                                        "<DataArray type=\"Float64\" format=\"ascii\">",
                                        "</DataArray>",
                                        "Name=\"connectivity\"",
                                        "Name=\"offsets\"",
                                        "Name=\"types\"",
                                        "format=\"binary\"",
                                        "<Cells>",
                                        " 5\n",
                                        " 10\n"};
  const std::vector<std::string> msh = {
      "$MeshFormat", "$EndMeshFormat", "2.2 0 8", "$Nodes",    "$EndNodes",      "$Elements",         "$EndElements",
      "$NOD",        "$ENDNOD",        "$ELM",    "$ENDELM",   "$PhysicalNames", "$EndPhysicalNames", " 4 ",
      " 2 ",         "$Comments",      "4.1 0 8", "$Entities", "$EndEntities"};
  const std::vector<std::string> tetgen = {"# ", " 3 0 0", " 4 0", " 4 1", "\n#--ele--\n", " 1 ", " 0 "};
  const std::vector<std::pair<std::string, const std::vector<std::string>*>> words = {
      {"obj", &obj},        {"off", &off},         {"stl_ascii", &stl}, {"stl_binary", &stl}, {"ply_ascii", &ply},
      {"ply_binary", &ply}, {"vtu_surface", &vtu}, {"gmsh", &msh},      {"tetgen", &tetgen},  {"tetgen_face", &tetgen},
      {"vtu_volume", &vtu}};
  for (Target& target : t)
    for (const auto& [name, list] : words)
      if (target.name == name) target.dictionary = *list;
  return t;
}

const Target& find_target(const std::string& name) {
  std::string names;
  for (const Target& t : targets()) {
    if (t.name == name) return t;
    names += (names.empty() ? "" : ", ") + t.name;
  }
  throw std::invalid_argument("unknown fuzz target '" + name + "' (targets: " + names + ")");
}

Outcome run_input(const Target& target, const std::string& bytes, const Workspace& workspace) {
  std::string message;
  try {
    target.run(bytes, workspace);
    return {Outcome::Kind::Accepted, ""};
  } catch (const std::exception& e) {
    message = e.what();
  } catch (...) {
    return {Outcome::Kind::Finding, "an exception not derived from std::exception"};
  }
  if (message.empty()) return {Outcome::Kind::Finding, "an empty error message"};
  if (message.find_first_of("\n\r") != std::string::npos)
    return {Outcome::Kind::Finding, "a message of several lines: " + message};
  bool named = false;
  for (const std::string& f : target.files) named = named || message.find(f) != std::string::npos;
  if (!named) return {Outcome::Kind::Finding, "a message that names no input file: " + message};
  return {Outcome::Kind::Rejected, message};
}

std::string message_kind(std::string m, const std::string& workspace) {
  for (size_t at; !workspace.empty() && (at = m.find(workspace)) != std::string::npos;)
    m.replace(at, workspace.size(), "");
  std::string out;
  for (size_t i = 0; i < m.size() && out.size() < 300;) {
    const char c = m[i];
    if (c == '\'') {
      const size_t close = m.find('\'', i + 1);
      out += "'...'";
      i = close == std::string::npos ? m.size() : close + 1;
    } else if ((c >= '0' && c <= '9') ||
               ((c == '-' || c == '+') && i + 1 < m.size() && m[i + 1] >= '0' && m[i + 1] <= '9')) {
      out += '#';
      for (++i; i < m.size() && (std::isdigit(static_cast<unsigned char>(m[i])) || std::strchr(".eE+-", m[i])); ++i) {
      }
    } else {
      out += c;
      ++i;
    }
  }
  return out;
}

}  // namespace tb::fuzz
