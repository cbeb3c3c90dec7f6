#include "field_output.h"

namespace softpack::io
{

FieldOutput::FieldOutput(MPI_Comm comm, const std::filesystem::path& directory,
                         const bodies::BodySet& bodies)
    : _cell_area(bodies.cell_reference_area())
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

  _file = std::make_unique<dolfinx::io::XDMFFile>(
      comm, directory / "fields.xdmf", "w");
  _file->write_mesh(*bodies.mesh());
}

FieldOutput::~FieldOutput()
{
  if (_file)
    _file->close();
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
}

} // namespace softpack::io
