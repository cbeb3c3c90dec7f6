#include "field_output.h"

#include <cstdio>
#include <fstream>
#include <hdf5.h>
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

/// Write every open HDF5 file's buffers and metadata to disk. dolfinx's
/// XDMFFile keeps fields.h5 open for the whole run, and a file killed before
/// its close is unreadable (HDF5's metadata lives in a cache): flushed after
/// each frame, a killed run keeps the frames its fields.xdmf lists.
void flush_open_hdf5_files()
{
  const ssize_t n = H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_FILE);
  if (n <= 0)
    return;
  std::vector<hid_t> ids(static_cast<std::size_t>(n));
  const ssize_t found =
      H5Fget_obj_ids(H5F_OBJ_ALL, H5F_OBJ_FILE, ids.size(), ids.data());
  for (ssize_t k = 0; k < found; ++k)
    if (H5Fflush(ids[k], H5F_SCOPE_GLOBAL) < 0)
      throw std::runtime_error("cannot flush fields.h5 to disk");
}

std::string data_item(const std::string& dims, const std::string& dataset,
                      const char* number_type = "Float")
{
  return "<DataItem Dimensions=\"" + dims + "\" NumberType=\"" + number_type +
         "\" Precision=\"8\" Format=\"HDF\">fields.h5:" + dataset +
         "</DataItem>";
}
} // namespace

FieldOutput::FieldOutput(MPI_Comm comm, const std::filesystem::path& directory,
                         const bodies::BodySet& bodies)
    : _xdmf(directory / "fields.xdmf"), _mesh_name(bodies.mesh()->name),
      _num_nodes(bodies.mesh()->geometry().x().size() / 3),
      _num_cells(bodies.cell_body().size()),
      _cell_area(bodies.cell_reference_area())
{
  auto Q =
      std::const_pointer_cast<dolfinx::fem::FunctionSpace>(bodies.cell_space());
  _psi = std::make_shared<dolfinx::fem::Function<double>>(Q);
  _psi->name = "Psi";
  _particle = std::make_shared<dolfinx::fem::Function<double>>(Q);
  _particle->name = "particle";
  const auto& dofmap = *Q->dofmap();
  std::span<double> id = _particle->x()->mutable_array();
  for (std::size_t c = 0; c < bodies.cell_body().size(); ++c)
    id[dofmap.cell_dofs(c)[0]] = bodies.cell_body()[c];

  _file = std::make_unique<dolfinx::io::XDMFFile>(comm, _xdmf, "w");
  _file->write_mesh(*bodies.mesh());
  flush_open_hdf5_files();
}

FieldOutput::~FieldOutput()
{
  if (_file)
    _file->close();
  try
  {
    write_xml();
  }
  catch (const std::exception&)
  {
    // A destructor must not throw; the last write_xml() stands.
  }
}

void FieldOutput::write(const bodies::BodySet& bodies, double t)
{
  const std::vector<double> energy = bodies.cell_strain_energy();
  const auto& dofmap = *_psi->function_space()->dofmap();
  std::span<double> psi = _psi->x()->mutable_array();
  for (std::size_t c = 0; c < energy.size(); ++c)
    psi[dofmap.cell_dofs(c)[0]] = energy[c] / _cell_area[c];
  auto u = std::const_pointer_cast<dolfinx::fem::Function<double>>(
      bodies.displacement_function());
  u->name = "displacement";
  _file->write_function(*u, t);
  _file->write_function(*_psi, t);
  _file->write_function(*_particle, t);
  flush_open_hdf5_files();
  _times.push_back(t);
  write_xml();
}

void FieldOutput::write_xml() const
{
  const std::string nodes = std::to_string(_num_nodes);
  const std::string cells = std::to_string(_num_cells);
  const std::string mesh = "/Mesh/" + _mesh_name;
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
