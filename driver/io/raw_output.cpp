#include "raw_output.h"

#include <bodies/placement.h>

#include <cstdio>
#include <iomanip>
#include <nlohmann/json.hpp>

namespace softpack::io
{

namespace
{
/// The components of a point or force column, and of the Cauchy integrals
/// (bodies/stress_average.h's order)
const char* const axes = "xyz";
const std::vector<std::string> cauchy_names = {"xx", "yy", "xy", "yx", "zz",
                                               "xz", "zx", "yz", "zy"};
/// Each body's integral of its Cauchy stress (stress_average.h), summed
/// over the bodies: the finite elements' estimate of the mean stress times
/// the box area (3D: volume), for analysis/stress.py.
void write_cauchy_totals(std::ofstream& out, std::span<const double> cauchy,
                         int size)
{
  for (int k = 0; k < size; ++k)
  {
    double total = 0;
    for (std::size_t b = 0; b < cauchy.size() / size; ++b)
      total += cauchy[size * b + k];
    out << ',' << total;
  }
}
} // namespace

RawOutput::RawOutput(const std::filesystem::path& directory,
                     const std::vector<std::string>& walls, int dim, bool cell)
    : _raw(directory / "raw"), _cell(cell), _dim(dim)
{
  std::filesystem::create_directories(_raw / "contacts");
  std::filesystem::remove(_raw / "done.json");
  _steps.open(_raw / "steps.csv");
  _particles.open(_raw / "particles.csv");
  if (!_steps || !_particles)
    throw std::runtime_error("cannot write in " + _raw.string());
  _steps << std::setprecision(12);
  _particles << std::setprecision(12);
  _steps
      << "step,time,time_step,stage,newton_iterations,nlgs_iterations,nlgs_"
         "error,"
         "nlgs_converged,contacts,active_contacts,intact_bonds,max_penetration";
  for (const std::string& name : walls)
  {
    for (int i = 0; i < _dim; ++i)
      _steps << ',' << name << '_' << axes[i];
    for (int i = 0; i < _dim; ++i)
      _steps << ',' << name << "_f" << axes[i];
  }
  if (_cell)
    _steps << ",cell_a1x,cell_a1y,cell_a2x,cell_a2y";
  _steps << (_dim == 3 ? ",phi,phi_base" : ",phi");
  _steps << ",strain_energy,kinetic_energy,wall_work,external_work,"
            "cell_work,rewrap,damping,friction,contact_normal,cohesion,bond,"
            "viscous,numerical,energy_"
            "residual,"
            "seconds,seconds_detection,seconds_assembly,seconds_factorization,"
            "seconds_delassus,seconds_nlgs,seconds_solves,refactorized,"
            "newton_unconverged_steps,nlgs_unconverged_steps,retried_steps,"
            "max_overlap_depth";
  std::string cauchy;
  for (int k = 0; k < cauchy_size(); ++k)
    cauchy += ",cauchy_" + cauchy_names[k];
  _steps << cauchy << '\n';
  _particles << "step,particle,area,strain_energy,reference_area" << cauchy
             << (_dim == 2 ? ",centroid_x,centroid_y,rotation\n"
                           : ",centroid_x,centroid_y,centroid_z\n");
}

void RawOutput::write(long step, const dynamics::MoreauJean& scheme,
                      const dynamics::StepReport& r, std::optional<double> phi,
                      double seconds, const bodies::BodySet& bodies,
                      const std::vector<WallRow>& walls,
                      std::span<const double> cauchy,
                      const dynamics::StepTimings& spent,
                      const dynamics::ContactForceAverage& average,
                      const ConvergenceCounts& interval, double overlap_depth)
{
  _steps << step << ',' << scheme.time() << ',' << r.time_step << ',' << _stage
         << ',' << r.newton_iterations << ',' << r.nlgs_iterations << ','
         << r.nlgs_error << ',' << (r.nlgs_converged ? 1 : 0) << ','
         << r.contacts << ',' << r.active_contacts << ','
         << scheme.intact_bonds() << ',' << r.max_penetration;
  for (const WallRow& w : walls)
  {
    for (int i = 0; i < _dim; ++i)
      _steps << ',' << w.point[i];
    for (int i = 0; i < _dim; ++i)
      _steps << ',' << w.force[i];
  }
  if (const auto& cell = scheme.cell())
    _steps << ',' << cell->a1[0] << ',' << cell->a1[1] << ',' << cell->a2[0]
           << ',' << cell->a2[1];
  const dynamics::EnergyBalance& e = scheme.energy();
  _steps << ',';
  if (phi)
    _steps << *phi;
  if (_dim == 3)
  {
    _steps << ',';
    if (_phi_base)
      _steps << *_phi_base;
  }
  _steps << ',' << e.strain << ',' << e.kinetic << ',' << e.wall_work << ','
         << e.external_work << ',' << e.cell_work << ',' << e.rewrap << ','
         << e.damping << ',' << e.friction << ',' << e.contact_normal << ','
         << e.cohesion << ',' << e.bond << ',' << e.viscous << ','
         << e.numerical << ',' << e.residual() << ',' << seconds << ','
         << spent.detection << ',' << spent.assembly << ','
         << spent.factorization << ',' << spent.delassus << ',' << spent.nlgs
         << ',' << spent.solves << ',' << (r.refactorized ? 1 : 0) << ','
         << interval.newton_unconverged_steps << ','
         << interval.nlgs_unconverged_steps << ',' << interval.retried_steps
         << ',' << overlap_depth;
  write_cauchy_totals(_steps, cauchy, cauchy_size());
  _steps << '\n';
  _steps.flush();
  if (_dim == 2)
  {
    write_particles(step, bodies, scheme.body_strain_energy(), cauchy);
    write_contacts(step, average);
  }
  else
  {
    write_particles_3d(step, bodies, scheme.body_strain_energy(), cauchy);
    write_contacts_3d(step, scheme);
  }
}

void RawOutput::write_particles(long step, const bodies::BodySet& bodies,
                                std::span<const double> energy,
                                std::span<const double> cauchy)
{
  const std::vector<double> area = bodies.body_current_area();
  const std::vector<bodies::Placement> where = bodies::placements(bodies);
  for (int b = 0; b < bodies.num_bodies(); ++b)
    _particles << step << ',' << b << ',' << area[b] << ',' << energy[b] << ','
               << bodies.body(b).reference_area << ',' << cauchy[4 * b] << ','
               << cauchy[4 * b + 1] << ',' << cauchy[4 * b + 2] << ','
               << cauchy[4 * b + 3] << ',' << where[b].x << ',' << where[b].y
               << ',' << where[b].rotation << '\n';
  _particles.flush();
}

void RawOutput::write_contacts(long step,
                               const dynamics::ContactForceAverage& average)
{
  char name[40];
  std::snprintf(name, sizeof(name), "step_%08ld.csv", step);
  const std::filesystem::path path = _raw / "contacts" / name;
  const std::filesystem::path tmp = _raw / "contacts" / ".tmp.csv";
  {
    std::ofstream out(tmp);
    out << std::setprecision(10);
    out << "candidate,node,antagonist,wall,segment0,segment1,xi,gap,fn,ft,fx,"
           "fy,steps";
    if (_cell)
      out << ",image1,image2";
    out << '\n';
    for (const dynamics::AveragedContactForce& m : average.contact_forces())
    {
      const dynamics::Contact& c = m.contact;
      const double fn = m.force[0] * c.n[0] + m.force[1] * c.n[1];
      const double ft = m.force[0] * c.t[0] + m.force[1] * c.t[1];
      out << c.candidate_body << ',' << c.candidate_node << ','
          << c.antagonist_body << ',' << c.wall << ',' << c.segment[0] << ','
          << c.segment[1] << ',' << c.xi << ',' << c.gap << ',' << fn << ','
          << ft << ',' << m.force[0] << ',' << m.force[1] << ',' << m.steps;
      if (_cell)
        out << ',' << c.image[0] << ',' << c.image[1];
      out << '\n';
    }
  }
  std::filesystem::rename(tmp, path);
}

void RawOutput::write_particles_3d(long step, const bodies::BodySet& bodies,
                                   std::span<const double> energy,
                                   std::span<const double> cauchy)
{
  const std::vector<double> volume = bodies.body_current_area();
  const std::vector<std::array<double, 3>> c = bodies::centroids_3d(bodies);
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    _particles << step << ',' << b << ',' << volume[b] << ',' << energy[b]
               << ',' << bodies.body(b).reference_area;
    for (int k = 0; k < 9; ++k)
      _particles << ',' << cauchy[9 * b + k];
    _particles << ',' << c[b][0] << ',' << c[b][1] << ',' << c[b][2] << '\n';
  }
  _particles.flush();
}

void RawOutput::write_contacts_3d(long step, const dynamics::MoreauJean& scheme)
{
  char name[40];
  std::snprintf(name, sizeof(name), "step_%08ld.csv", step);
  const std::filesystem::path path = _raw / "contacts" / name;
  const std::filesystem::path tmp = _raw / "contacts" / ".tmp.csv";
  const std::vector<dynamics::Contact3D>& contacts = scheme.contacts_3d();
  const std::vector<double>& R = scheme.impulses();
  const double h = scheme.time_step();
  {
    std::ofstream out(tmp);
    out << std::setprecision(10);
    out << "candidate,node,antagonist,wall,triangle0,triangle1,triangle2,"
           "gap,fn,ft1,ft2,fx,fy,fz\n";
    for (std::size_t a = 0; a < contacts.size(); ++a)
    {
      const dynamics::Contact3D& c = contacts[a];
      const double fn = R[3 * a] / h, ft1 = R[3 * a + 1] / h,
                   ft2 = R[3 * a + 2] / h;
      out << c.candidate_body << ',' << c.candidate_node << ','
          << c.antagonist_body << ',' << c.wall << ',' << c.triangle[0] << ','
          << c.triangle[1] << ',' << c.triangle[2] << ',' << c.gap << ',' << fn
          << ',' << ft1 << ',' << ft2;
      for (int i = 0; i < 3; ++i)
        out << ',' << fn * c.n[i] + ft1 * c.t1[i] + ft2 * c.t2[i];
      out << '\n';
    }
  }
  std::filesystem::rename(tmp, path);
}

void RawOutput::finish(long steps, double seconds, const std::string& reason,
                       const dynamics::StepTimings& spent, int factorizations,
                       const RunChecks& checks, const nlohmann::json& extra)
{
  nlohmann::json done = {
      {"steps", steps},
      {"seconds", seconds},
      {"reason", reason},
      {"factorizations", factorizations},
      {"seconds_by_part",
       {{"detection", spent.detection},
        {"assembly", spent.assembly},
        {"factorization", spent.factorization},
        {"delassus", spent.delassus},
        {"nlgs", spent.nlgs},
        {"solves", spent.solves}}},
      {"converged", checks.total.converged()},
      {"newton_unconverged_steps", checks.total.newton_unconverged_steps},
      {"nlgs_unconverged_steps", checks.total.nlgs_unconverged_steps},
      {"retried_steps", checks.total.retried_steps},
      {"failed_contact_problems_written", checks.problems_written},
      {"failed_contact_problems_not_written", checks.problems_not_written},
      {"max_overlap_depth", checks.max_overlap_depth},
      {"overlap_steps", checks.overlap_steps},
      {"newton_iterations", checks.newton_iterations},
      {"nlgs_sweeps", checks.nlgs_sweeps}};
  if (extra.is_object())
    done.update(extra);
  const std::filesystem::path tmp = _raw / ".done.json";
  std::ofstream(tmp) << done.dump(2) << '\n';
  std::filesystem::rename(tmp, _raw / "done.json");
}

} // namespace softpack::io
