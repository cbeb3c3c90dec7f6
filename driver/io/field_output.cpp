#include "field_output.h"

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
/// dolfinx's name of a time in the HDF5 file: the time with 17 significant
/// digits, '.' replaced by '_' (as its XML references it).
std::string time_key(double t)
{
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", t);
  std::string key = text;
  for (char& c : key)
    if (c == '.')
      c = '_';
  return key;
}

std::string data_item(const std::string& dims, const std::string& dataset,
                      const char* number_type = "Float")
{
  return "<DataItem Dimensions=\"" + dims + "\" NumberType=\"" + number_type +
         "\" Precision=\"8\" Format=\"HDF\">fields.h5:" + dataset +
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
} // namespace

FieldOutput::FieldOutput(const std::filesystem::path& directory,
                         const bodies::BodySet& bodies, bool continued)
    : _xdmf(directory / "fields.xdmf"),
      _num_nodes(bodies.num_global_dofs() / 2),
      _num_cells(bodies.cell_body().size()),
      _cell_area(bodies.cell_reference_area()),
      _particle(bodies.cell_body().begin(), bodies.cell_body().end())
{
  if (bodies.unstored_node() >= 0)
    throw std::logic_error("FieldOutput: the bodies store some nodes only");
  const std::filesystem::path path = directory / "fields.h5";
  if (continued && std::filesystem::exists(path))
  {
    open_existing(path);
    return;
  }
  _file = std::make_unique<h5::Handle>(
      H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
      H5Fclose);
  if (!_file->valid())
    throw std::runtime_error(path.string() + ": cannot be created");
  const hid_t f = _file->get();
  for (const char* group :
       {"/Mesh", "/Mesh/mesh", "/Function", "/Function/displacement",
        "/Function/Psi", "/Function/particle"})
    h5::create_group(f, group);
  h5::write_table(f, "/Mesh/mesh/geometry", bodies.reference_coordinates(), 2);
  std::vector<std::int64_t> topology;
  topology.reserve(3 * _num_cells);
  for (const auto& cell : bodies.cell_global_nodes())
    topology.insert(topology.end(), cell.begin(), cell.end());
  h5::write_table(f, "/Mesh/mesh/topology",
                  std::span<const std::int64_t>(topology), 3);
  flush();
}

FieldOutput::~FieldOutput()
{
  _file.reset();
  try
  {
    write_xml();
  }
  catch (const std::exception&)
  {
    // A destructor must not throw; the last write_xml() stands.
  }
}

void FieldOutput::open_existing(const std::filesystem::path& path)
{
  _file = std::make_unique<h5::Handle>(
      H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
  if (!_file->valid())
    throw std::runtime_error(path.string() +
                             ": cannot be opened to continue it");
  const hid_t f = _file->get();
  const hsize_t nodes = rows(f, "/Mesh/mesh/geometry"),
                cells = rows(f, "/Mesh/mesh/topology");
  if (nodes != _num_nodes || cells != _num_cells)
    throw std::runtime_error(
        path.string() + ": holds another mesh (" + std::to_string(nodes) +
        " nodes, " + std::to_string(cells) + " cells): not this run's fields");
  const h5::Handle group(H5Gopen2(f, "/Function/displacement", H5P_DEFAULT),
                         H5Gclose);
  H5G_info_t info;
  if (!group.valid() || H5Gget_info(group.get(), &info) < 0)
    throw std::runtime_error(path.string() + ": no /Function/displacement");
  for (hsize_t k = 0; k < info.nlinks; ++k)
  {
    char name[64];
    H5Lget_name_by_idx(group.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, name,
                       sizeof(name), H5P_DEFAULT);
    std::string text = name;
    std::replace(text.begin(), text.end(), '_', '.');
    _times.push_back(std::stod(text));
  }
  std::sort(_times.begin(), _times.end());
}

void FieldOutput::continue_after(double t)
{
  std::vector<double> kept;
  for (const double time : _times)
    if (time <= t)
      kept.push_back(time);
    else
      remove_frame(time_key(time));
  _times = std::move(kept);
  flush();
  write_xml();
}

void FieldOutput::remove_frame(const std::string& key) const
{
  for (const char* name : {"displacement", "Psi", "particle"})
  {
    const std::string path = std::string("/Function/") + name + "/" + key;
    if (h5::exists(_file->get(), path) &&
        H5Ldelete(_file->get(), path.c_str(), H5P_DEFAULT) < 0)
      throw std::runtime_error("fields.h5: cannot remove " + path);
  }
}

void FieldOutput::flush() const
{
  if (H5Fflush(_file->get(), H5F_SCOPE_GLOBAL) < 0)
    throw std::runtime_error("cannot flush fields.h5 to disk");
}

void FieldOutput::write(std::span<const double> u,
                        std::span<const double> cell_energy, double t)
{
  if (u.size() != 2 * _num_nodes || cell_energy.size() != _num_cells)
    throw std::invalid_argument("FieldOutput::write: not the mesh's sizes");
  const hid_t f = _file->get();
  const std::string key = time_key(t);
  const bool again = std::find(_times.begin(), _times.end(), t) != _times.end();
  if (again) // a continued run's first frame, at the state's time
    remove_frame(key);
  std::vector<double> u3(3 * _num_nodes, 0.0); // XDMF vectors have 3 parts
  for (std::size_t n = 0; n < _num_nodes; ++n)
    for (int c = 0; c < 2; ++c)
      u3[3 * n + c] = u[2 * n + c];
  h5::write_table(f, "/Function/displacement/" + key, u3, 3);
  std::vector<double> psi(cell_energy.begin(), cell_energy.end());
  for (std::size_t c = 0; c < psi.size(); ++c)
    psi[c] /= _cell_area[c];
  h5::write_table(f, "/Function/Psi/" + key, psi, 1);
  h5::write_table(f, "/Function/particle/" + key, _particle, 1);
  flush();
  if (!again)
    _times.push_back(t);
  write_xml();
}

void FieldOutput::write_xml() const
{
  const std::string nodes = std::to_string(_num_nodes);
  const std::string cells = std::to_string(_num_cells);
  const std::string mesh = "/Mesh/mesh";
  std::ostringstream x;
  x << "<?xml version=\"1.0\"?>\n"
       "<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n"
       "  <Domain>\n"
       "    <Grid Name=\"fields\" GridType=\"Collection\" "
       "CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < _times.size(); ++k)
  {
    const std::string key = time_key(_times[k]);
    x << "      <Grid Name=\"fields\" GridType=\"Uniform\">\n";
    if (k == 0)
      x << "        <Topology TopologyType=\"Triangle\" NumberOfElements=\""
        << cells << "\" NodesPerElement=\"3\">\n          "
        << data_item(cells + " 3", mesh + "/topology", "Int")
        << "\n        </Topology>\n"
           "        <Geometry GeometryType=\"XY\">\n          "
        << data_item(nodes + " 2", mesh + "/geometry")
        << "\n        </Geometry>\n";
    else
      x << "        <xi:include xpointer=\"xpointer(/Xdmf/Domain/Grid/Grid[1]/"
           "*[self::Topology or self::Geometry])\" />\n";
    char time[40];
    std::snprintf(time, sizeof(time), "%.17g", _times[k]);
    x << "        <Time Value=\"" << time << "\" />\n"
      << "        <Attribute Name=\"displacement\" AttributeType=\"Vector\" "
         "Center=\"Node\">\n          "
      << data_item(nodes + " 3", "/Function/displacement/" + key)
      << "\n        </Attribute>\n";
    for (const char* name : {"Psi", "particle"})
      x << "        <Attribute Name=\"" << name
        << "\" AttributeType=\"Scalar\" Center=\"Cell\">\n          "
        << data_item(cells + " 1", std::string("/Function/") + name + "/" + key)
        << "\n        </Attribute>\n";
    x << "      </Grid>\n";
  }
  x << "    </Grid>\n  </Domain>\n</Xdmf>\n";
  const std::filesystem::path tmp = _xdmf.string() + ".tmp";
  std::ofstream(tmp) << x.str();
  std::filesystem::rename(tmp, _xdmf);
}

} // namespace softpack::io
