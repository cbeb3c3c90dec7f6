#include "field_output.h"

#include <io/h5_helpers.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace softpack::io
{
namespace
{
constexpr const char* mesh_file = "fields.h5";
constexpr const char* frame_directory = "fields";
constexpr const char* functions[] = {"displacement", "Psi", "particle"};

/// dolfinx's name of a time in the HDF5 file: the time with 17 significant
/// digits, '.' replaced by '_' (as its XML references it).
std::string time_key(double t)
{
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", t);
  std::string key = text;
  std::replace(key.begin(), key.end(), '.', '_');
  return key;
}

double key_time(std::string key)
{
  std::replace(key.begin(), key.end(), '_', '.');
  return std::stod(key);
}

std::string data_item(const std::string& dims, const std::string& file,
                      const std::string& dataset,
                      const char* number_type = "Float")
{
  return "<DataItem Dimensions=\"" + dims + "\" NumberType=\"" + number_type +
         "\" Precision=\"8\" Format=\"HDF\">" + file + ":" + dataset +
         "</DataItem>";
}

/// The number of rows of a dataset (0 if absent)
hsize_t rows(hid_t f, const std::string& path)
{
  if (!h5::exists(f, path))
    return 0;
  const h5::Handle data(H5Dopen2(f, path.c_str(), H5P_DEFAULT), H5Dclose);
  const h5::Handle space(H5Dget_space(data.get()), H5Sclose);
  hsize_t dims[2] = {0, 0};
  if (H5Sget_simple_extent_ndims(space.get()) < 1 ||
      H5Sget_simple_extent_dims(space.get(), dims, nullptr) < 0)
    return 0;
  return dims[0];
}

/// The keys of the links of a group (none if it is absent)
std::vector<std::string> link_names(hid_t f, const std::string& path)
{
  std::vector<std::string> names;
  if (!h5::exists(f, path))
    return names;
  const h5::Handle group(H5Gopen2(f, path.c_str(), H5P_DEFAULT), H5Gclose);
  H5G_info_t info;
  if (!group.valid() || H5Gget_info(group.get(), &info) < 0)
    throw std::runtime_error(std::string(mesh_file) + ": unreadable " + path);
  for (hsize_t k = 0; k < info.nlinks; ++k)
  {
    char name[64];
    H5Lget_name_by_idx(group.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, name,
                       sizeof(name), H5P_DEFAULT);
    names.emplace_back(name);
  }
  return names;
}

/// Create an HDF5 file under a temporary name, fill it, close it and rename
/// it to `path`: a reader (or a killed writer) never sees it half written.
template <typename Fill>
void write_whole(const std::filesystem::path& path, Fill fill)
{
  const std::filesystem::path tmp =
      path.parent_path() / ("." + path.filename().string() + ".tmp");
  try
  {
    const h5::Handle file(
        H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
        H5Fclose);
    if (!file.valid())
      throw std::runtime_error(path.string() + ": cannot be created");
    fill(file.get());
    if (H5Fflush(file.get(), H5F_SCOPE_GLOBAL) < 0)
      throw std::runtime_error(path.string() + ": cannot be written whole");
  }
  catch (...)
  {
    std::filesystem::remove(tmp); // no part left beside the whole files
    throw;
  }
  std::filesystem::rename(tmp, path);
}
} // namespace

FieldOutput::FieldOutput(const std::filesystem::path& directory,
                         const bodies::BodySet& bodies, bool continued)
    : _directory(directory), _dim(bodies.dim()),
      _num_nodes(bodies.num_global_dofs() / bodies.dim()),
      _num_cells(bodies.cell_body().size()),
      _cell_area(bodies.cell_reference_area()),
      _particle(bodies.cell_body().begin(), bodies.cell_body().end())
{
  if (bodies.unstored_node() >= 0)
    throw std::logic_error("FieldOutput: the bodies store some nodes only");
  if (continued && std::filesystem::exists(directory / mesh_file))
    open_existing();
  else
    create(bodies);
}

void FieldOutput::create(const bodies::BodySet& bodies)
{
  std::filesystem::remove_all(_directory / frame_directory);
  std::filesystem::create_directory(_directory / frame_directory);
  std::vector<std::int64_t> topology;
  topology.reserve((_dim + 1) * _num_cells);
  for (const auto& cell : bodies.cell_global_nodes())
    topology.insert(topology.end(), cell.begin(), cell.end());
  write_whole(_directory / mesh_file,
              [&](hid_t f)
              {
                for (const char* group : {"/Mesh", "/Mesh/mesh"})
                  h5::create_group(f, group);
                h5::write_table(f, "/Mesh/mesh/geometry",
                                bodies.reference_coordinates(), _dim);
                h5::write_table(f, "/Mesh/mesh/topology",
                                std::span<const std::int64_t>(topology),
                                _dim + 1);
              });
  write_xml();
}

void FieldOutput::open_existing()
{
  const std::filesystem::path path = _directory / mesh_file;
  {
    const h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT),
                          H5Fclose);
    if (!file.valid())
      throw std::runtime_error(path.string() +
                               ": cannot be opened to continue it");
    const hsize_t nodes = rows(file.get(), "/Mesh/mesh/geometry"),
                  cells = rows(file.get(), "/Mesh/mesh/topology");
    if (nodes != _num_nodes || cells != _num_cells)
      throw std::runtime_error(path.string() + ": holds another mesh (" +
                               std::to_string(nodes) + " nodes, " +
                               std::to_string(cells) +
                               " cells): not this run's fields");
    for (const std::string& key :
         link_names(file.get(), "/Function/displacement"))
      _frames.push_back({key_time(key), mesh_file});
  }
  const std::filesystem::path frames = _directory / frame_directory;
  std::filesystem::create_directories(frames);
  for (const auto& entry : std::filesystem::directory_iterator(frames))
  {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("."))
      std::filesystem::remove(entry.path()); // a killed driver's part
    else if (entry.path().extension() == ".h5")
      _frames.push_back({key_time(entry.path().stem().string()),
                         std::string(frame_directory) + "/" + name});
  }
  // A frame in both files (the state's time, written again by a resumed
  // earlier version): fields/ holds the later one.
  std::stable_sort(_frames.begin(), _frames.end(),
                   [](const Frame& a, const Frame& b)
                   { return a.time < b.time; });
  for (std::size_t k = 0; k + 1 < _frames.size();)
    if (_frames[k].time == _frames[k + 1].time)
      _frames.erase(_frames.begin() + k);
    else
      ++k;
}

void FieldOutput::continue_after(double t)
{
  remove_inner_frames_after(t);
  std::vector<Frame> kept;
  for (const Frame& frame : _frames)
    if (frame.time <= t)
      kept.push_back(frame);
    else if (frame.file != mesh_file)
      std::filesystem::remove(_directory / frame.file);
  _frames = std::move(kept);
  write_xml();
}

void FieldOutput::remove_inner_frames_after(double t) const
{
  const std::filesystem::path path = _directory / mesh_file;
  if (std::none_of(_frames.begin(), _frames.end(),
                   [&](const Frame& frame)
                   { return frame.file == mesh_file && frame.time > t; }))
    return;
  const h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT),
                        H5Fclose);
  for (const Frame& frame : _frames)
    for (const char* name : functions)
    {
      const std::string link =
          std::string("/Function/") + name + "/" + time_key(frame.time);
      if (frame.file == mesh_file && frame.time > t &&
          h5::exists(file.get(), link) &&
          H5Ldelete(file.get(), link.c_str(), H5P_DEFAULT) < 0)
        throw std::runtime_error(path.string() + ": cannot remove " + link);
    }
}

void FieldOutput::write(std::span<const double> u,
                        std::span<const double> cell_energy, double t)
{
  const auto dim = static_cast<std::size_t>(_dim);
  if (u.size() != dim * _num_nodes || cell_energy.size() != _num_cells)
    throw std::invalid_argument("FieldOutput::write: not the mesh's sizes");
  const std::string key = time_key(t);
  std::vector<double> u3(3 * _num_nodes, 0.0); // XDMF vectors have 3 parts
  for (std::size_t n = 0; n < _num_nodes; ++n)
    for (std::size_t c = 0; c < dim; ++c)
      u3[3 * n + c] = u[dim * n + c];
  std::vector<double> psi(cell_energy.begin(), cell_energy.end());
  for (std::size_t c = 0; c < psi.size(); ++c)
    psi[c] /= _cell_area[c];
  const std::string file = std::string(frame_directory) + "/" + key + ".h5";
  write_whole(_directory / file,
              [&](hid_t f)
              {
                h5::create_group(f, "/Function");
                for (const char* name : functions)
                  h5::create_group(f, std::string("/Function/") + name);
                h5::write_table(f, "/Function/displacement/" + key, u3, 3);
                h5::write_table(f, "/Function/Psi/" + key, psi, 1);
                h5::write_table(f, "/Function/particle/" + key, _particle, 1);
              });
  const auto at =
      std::find_if(_frames.begin(), _frames.end(),
                   [&](const Frame& frame) { return frame.time >= t; });
  if (at != _frames.end() && at->time == t) // a continued run's first frame
    at->file = file;
  else
    _frames.insert(at, {t, file});
  write_xml();
}

void FieldOutput::write_xml() const
{
  const std::string nodes = std::to_string(_num_nodes);
  const std::string cells = std::to_string(_num_cells);
  const std::string per_cell = std::to_string(_dim + 1);
  const bool solid = _dim == 3;
  const std::string mesh = "/Mesh/mesh";
  std::ostringstream x;
  x << "<?xml version=\"1.0\"?>\n"
       "<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n"
       "  <Domain>\n"
       "    <Grid Name=\"fields\" GridType=\"Collection\" "
       "CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < _frames.size(); ++k)
  {
    const std::string key = time_key(_frames[k].time);
    const std::string& file = _frames[k].file;
    x << "      <Grid Name=\"fields\" GridType=\"Uniform\">\n";
    if (k == 0)
      x << "        <Topology TopologyType=\""
        << (solid ? "Tetrahedron" : "Triangle") << "\" NumberOfElements=\""
        << cells << "\" NodesPerElement=\"" << per_cell << "\">\n          "
        << data_item(cells + " " + per_cell, mesh_file, mesh + "/topology",
                     "Int")
        << "\n        </Topology>\n"
           "        <Geometry GeometryType=\""
        << (solid ? "XYZ" : "XY") << "\">\n          "
        << data_item(nodes + " " + std::to_string(_dim), mesh_file,
                     mesh + "/geometry")
        << "\n        </Geometry>\n";
    else
      x << "        <xi:include xpointer=\"xpointer(/Xdmf/Domain/Grid/Grid[1]/"
           "*[self::Topology or self::Geometry])\" />\n";
    char time[40];
    std::snprintf(time, sizeof(time), "%.17g", _frames[k].time);
    x << "        <Time Value=\"" << time << "\" />\n"
      << "        <Attribute Name=\"displacement\" AttributeType=\"Vector\" "
         "Center=\"Node\">\n          "
      << data_item(nodes + " 3", file, "/Function/displacement/" + key)
      << "\n        </Attribute>\n";
    for (const char* name : {"Psi", "particle"})
      x << "        <Attribute Name=\"" << name
        << "\" AttributeType=\"Scalar\" Center=\"Cell\">\n          "
        << data_item(cells + " 1", file,
                     std::string("/Function/") + name + "/" + key)
        << "\n        </Attribute>\n";
    x << "      </Grid>\n";
  }
  x << "    </Grid>\n  </Domain>\n</Xdmf>\n";
  const std::filesystem::path xdmf = _directory / "fields.xdmf";
  const std::filesystem::path tmp = _directory / ".fields.xdmf.tmp";
  {
    std::ofstream out(tmp);
    out << x.str();
    if (!out.flush())
      throw std::runtime_error(xdmf.string() + ": cannot be written");
  }
  std::filesystem::rename(tmp, xdmf);
}

} // namespace softpack::io
