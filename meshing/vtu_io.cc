// ASCII VTK unstructured-grid (.vtu) writing and reading. ASCII keeps the files
// diff-able and byte-for-byte deterministic; ParaView and meshio open them.
#include <iomanip>
#include <sstream>

#include "atomic_file.h"
#include "mesh_io.h"
#include "text_parsing.h"

namespace tb {
namespace {

constexpr int kVtkVertex = 1, kVtkTriangle = 5, kVtkTetra = 10;

void write_data_array(std::ostringstream& os, const std::string& name, const Eigen::MatrixXd& a) {
  os << "<DataArray type=\"Float64\" Name=\"" << name << "\" NumberOfComponents=\"" << a.cols()
     << "\" format=\"ascii\">\n";
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    for (Eigen::Index j = 0; j < a.cols(); ++j) os << (j ? " " : "") << a(i, j);
    os << '\n';
  }
  os << "</DataArray>\n";
}

template <class Cells>
std::string vtu_text(const std::string& path, const Points& V, const Cells& cells, int vtk_type,
                     const std::vector<PointField>& fields) {
  std::ostringstream os;
  os << std::setprecision(17);
  os << "<?xml version=\"1.0\"?>\n"
     << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
     << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << V.rows() << "\" NumberOfCells=\"" << cells.rows()
     << "\">\n<PointData>\n";
  for (const auto& f : fields) {
    if (f.values.rows() != V.rows())
      throw std::runtime_error(path + ": field '" + f.name + "' has " + std::to_string(f.values.rows()) +
                               " values for " + std::to_string(V.rows()) + " points");
    write_data_array(os, f.name, f.values);
  }
  os << "</PointData>\n<Points>\n";
  write_data_array(os, "Points", V);
  os << "</Points>\n<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
  for (Eigen::Index c = 0; c < cells.rows(); ++c) {
    for (Eigen::Index k = 0; k < cells.cols(); ++k) os << (k ? " " : "") << cells(c, k);
    os << '\n';
  }
  os << "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
  for (Eigen::Index c = 0; c < cells.rows(); ++c) os << (c + 1) * cells.cols() << '\n';
  os << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (Eigen::Index c = 0; c < cells.rows(); ++c) os << vtk_type << '\n';
  os << "</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  return os.str();
}

/// The text between the '>' closing the DataArray tag that contains `key` and the
/// next "</DataArray>", searching from `from`.
std::string data_array_text(const std::string& file, const std::string& xml, const std::string& key, size_t from = 0) {
  const size_t k = xml.find(key, from);
  if (k == std::string::npos) throw MeshError(file, "VTU lacks " + key);
  const size_t tag = xml.rfind("<DataArray", k);
  const size_t open_end = xml.find('>', k);
  const size_t close = xml.find("</DataArray>", open_end);
  if (tag == std::string::npos || open_end == std::string::npos || close == std::string::npos)
    throw MeshError(file, "truncated VTU (unterminated DataArray)");
  const std::string header = xml.substr(tag, open_end - tag);
  if (header.find("format=\"ascii\"") == std::string::npos)
    throw MeshError(file, "only ASCII VTU is supported (binary or appended data found)");
  return xml.substr(open_end + 1, close - open_end - 1);
}

template <class T>
std::vector<T> parse_numbers(const std::string& file, const std::string& text, const std::string& what) {
  std::istringstream ss(text);
  std::vector<T> out;
  std::string tok;
  while (ss >> tok) {
    std::istringstream ts(tok);
    T v;
    if (!(ts >> v) || !ts.eof()) throw MeshError(file, "malformed number '" + detail::shown(tok) + "' in " + what);
    if constexpr (std::is_floating_point_v<T>)
      if (!std::isfinite(v)) throw MeshError(file, "NaN or Inf in " + what);
    out.push_back(v);
  }
  return out;
}

}  // namespace

void write_surface_vtu(const std::string& path, const SurfaceMesh& m, const std::vector<PointField>& fields) {
  write_file_atomically(path, vtu_text(path, m.V, m.F, kVtkTriangle, fields));
}

void write_volume_vtu(const std::string& path, const TetMesh& m, const std::vector<PointField>& fields) {
  write_file_atomically(path, vtu_text(path, m.V, m.T, kVtkTetra, fields));
}

void write_points_vtu(const std::string& path, const Points& P, const std::vector<PointField>& fields) {
  Eigen::Matrix<int, Eigen::Dynamic, 1> cells(P.rows());
  for (Eigen::Index i = 0; i < P.rows(); ++i) cells(i) = static_cast<int>(i);
  write_file_atomically(path, vtu_text(path, P, cells, kVtkVertex, fields));
}

void write_obj(const std::string& path, const SurfaceMesh& m) {
  std::ostringstream os;
  os << std::setprecision(17);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) os << "v " << m.V(i, 0) << ' ' << m.V(i, 1) << ' ' << m.V(i, 2) << '\n';
  for (Eigen::Index t = 0; t < m.F.rows(); ++t)
    os << "f " << m.F(t, 0) + 1 << ' ' << m.F(t, 1) + 1 << ' ' << m.F(t, 2) + 1 << '\n';
  write_file_atomically(path, os.str());
}

namespace detail {

VtuCells read_vtu_cells(const std::string& file, int vtk_cell_type, int nodes_per_cell) {
  const std::string xml = read_file(file);
  if (xml.find("<VTKFile") == std::string::npos || xml.find("UnstructuredGrid") == std::string::npos)
    throw MeshError(file, "not a VTK unstructured grid (.vtu) file");
  const size_t points_at = xml.find("<Points>");
  if (points_at == std::string::npos) throw MeshError(file, "VTU lacks <Points>");
  const auto xyz = parse_numbers<double>(file, data_array_text(file, xml, "<DataArray", points_at), "Points");
  const auto conn = parse_numbers<long>(file, data_array_text(file, xml, "Name=\"connectivity\""), "connectivity");
  const auto offs = parse_numbers<long>(file, data_array_text(file, xml, "Name=\"offsets\""), "offsets");
  const auto types = parse_numbers<int>(file, data_array_text(file, xml, "Name=\"types\""), "types");
  if (xyz.size() % 3) throw MeshError(file, "Points array length is not a multiple of 3");
  if (offs.size() != types.size()) throw MeshError(file, "offsets and types differ in length");
  VtuCells out;
  const long nv = static_cast<long>(xyz.size() / 3);
  out.V.resize(nv, 3);
  for (long i = 0; i < nv; ++i)
    for (int d = 0; d < 3; ++d) out.V(i, d) = xyz[static_cast<size_t>(3 * i + d)];
  std::vector<long> picked;
  long start = 0, bad = 0;
  for (size_t c = 0; c < types.size(); ++c) {
    const long end = offs[c];
    if (end < start || end > static_cast<long>(conn.size())) throw MeshError(file, "offsets out of range");
    if (types[c] == vtk_cell_type && end - start == nodes_per_cell)
      for (long k = start; k < end; ++k) {
        if (conn[static_cast<size_t>(k)] < 0 || conn[static_cast<size_t>(k)] >= nv) ++bad;
        picked.push_back(conn[static_cast<size_t>(k)]);
      }
    start = end;
  }
  if (bad)
    throw MeshError(file, std::to_string(bad) + " cell point indices out of range [0, " + std::to_string(nv) + ")");
  out.cells.resize(static_cast<Eigen::Index>(picked.size()) / nodes_per_cell, nodes_per_cell);
  for (size_t k = 0; k < picked.size(); ++k)
    out.cells(static_cast<Eigen::Index>(k) / nodes_per_cell, static_cast<Eigen::Index>(k) % nodes_per_cell) =
        static_cast<int>(picked[k]);
  return out;
}

}  // namespace detail
}  // namespace tb
