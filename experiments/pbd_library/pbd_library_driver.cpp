// The PositionBasedDynamics library (InteractiveComputerGraphics, Jan Bender et al.)
// on tissuebench's PBD problem, to time it side by side with tissuebench's own
// solver (issue 16; scripts/pbd_library_comparison builds and runs this). Not part
// of tissuebench's build: the library is no dependency of the project.
//
// The problem is the pbd model's (models/numerics/pbd/pbd_solver.cc), built with the
// library's own objects: the surface as a TriangleModel of a SimulationModel, a
// DistanceConstraint on every edge (addClothConstraints, method 1) and a
// DihedralConstraint on every interior edge (addBendingConstraints, method 1),
// stiffness 1, masses lumped as tb::pbd::lumped_surface_masses (density x enclosed
// volume, shared in proportion to one third of the incident triangle area),
// vertices in the support box fixed (mass 0, inverse mass 0), no gravity, and the
// library's TimeStepController with 1 sub-step, `iterations` position iterations
// and 0 velocity iterations (its constraint groups are swept in parallel by
// OpenMP: OMP_NUM_THREADS). Per frame, as tissuebench's eq. (31)-(32): the
// loaded vertex's velocity += dt w f (f ramped over the first `ramp` frames), every
// velocity *= (1 - damping), then TimeStepController::step (x += dt v, projection,
// v = (x - x_old) / dt). The timed frame is all of that.
//
// Writes one JSON object (stdout or --out): per-frame times, their median and p95
// after the ramp (linear interpolation between order statistics, as tissuebench's
// runner), the constraint counts, and the loaded vertex's displacement.
#include <omp.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "Common/Common.h"
#include "Simulation/Constraints.h"
#include "Simulation/Simulation.h"
#include "Simulation/SimulationModel.h"
#include "Simulation/TimeManager.h"
#include "Simulation/TimeStepController.h"
#include "Utils/Logger.h"
#include "Utils/Timing.h"

INIT_LOGGING
INIT_TIMING

using namespace PBD;

namespace {

struct Options {
  std::string surface, out;
  int frames = 300, ramp = 50, iterations = 10;
  double time_step = 0.01, density = 1000, damping = 0.05, stiffness = 1;
  Eigen::Vector3d force{0, 0, 1}, load_point{0, 0, 0.1};
  Eigen::Vector3d support_min{-1, -1, -1e-9}, support_max{1, 1, 1e-9};
};

[[noreturn]] void usage(const std::string& why) {
  std::cerr << "pbd_library_driver: " << why << "\n"
            << "usage: pbd_library_driver --surface FILE.obj [--frames N] [--ramp N] [--iterations N]\n"
            << "         [--time-step S] [--density KG_M3] [--damping F] [--stiffness K] [--force FX FY FZ]\n"
            << "         [--load-point X Y Z] [--support-min X Y Z] [--support-max X Y Z] [--out FILE.json]\n"
            << "threads: OMP_NUM_THREADS\n";
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  auto number = [&](int& i) {
    if (++i >= argc) usage(std::string("a number expected after ") + argv[i - 1]);
    char* end = nullptr;
    const double v = std::strtod(argv[i], &end);
    if (*end) usage(std::string("not a number: ") + argv[i]);
    return v;
  };
  auto vec = [&](int& i) {
    Eigen::Vector3d v;
    for (int k = 0; k < 3; ++k) v(k) = number(i);
    return v;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--surface" && i + 1 < argc)
      o.surface = argv[++i];
    else if (a == "--out" && i + 1 < argc)
      o.out = argv[++i];
    else if (a == "--frames")
      o.frames = static_cast<int>(number(i));
    else if (a == "--ramp")
      o.ramp = static_cast<int>(number(i));
    else if (a == "--iterations")
      o.iterations = static_cast<int>(number(i));
    else if (a == "--time-step")
      o.time_step = number(i);
    else if (a == "--density")
      o.density = number(i);
    else if (a == "--damping")
      o.damping = number(i);
    else if (a == "--stiffness")
      o.stiffness = number(i);
    else if (a == "--force")
      o.force = vec(i);
    else if (a == "--load-point")
      o.load_point = vec(i);
    else if (a == "--support-min")
      o.support_min = vec(i);
    else if (a == "--support-max")
      o.support_max = vec(i);
    else
      usage("unknown argument " + a);
  }
  if (o.surface.empty()) usage("--surface is required");
  if (o.frames <= o.ramp) usage("--frames must exceed --ramp (the frames after the ramp are timed)");
  return o;
}

/// A triangle OBJ in double precision ("v x y z", "f a b c", 1-based; a/b/c
/// forms accepted). The library's OBJLoader reads floats; tissuebench writes 17 digits.
void read_obj(const std::string& path, std::vector<Vector3r>& V, std::vector<unsigned int>& F) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v") {
      double x, y, z;
      if (!(s >> x >> y >> z)) throw std::runtime_error(path + ": bad vertex line: " + line);
      V.emplace_back(static_cast<Real>(x), static_cast<Real>(y), static_cast<Real>(z));
    } else if (tag == "f") {
      std::string w;
      int n = 0;
      while (s >> w) {
        F.push_back(static_cast<unsigned int>(std::stoi(w.substr(0, w.find('/'))) - 1));
        ++n;
      }
      if (n != 3) throw std::runtime_error(path + ": only triangles are supported: " + line);
    }
  }
  if (V.empty() || F.empty()) throw std::runtime_error(path + ": no triangles");
}

double quantile(std::vector<double> s, double q) {  // as tissuebench's timing_stats
  std::sort(s.begin(), s.end());
  const double pos = q * static_cast<double>(s.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, s.size() - 1);
  return s[lo] + (pos - static_cast<double>(lo)) * (s[hi] - s[lo]);
}

std::string json_array(const std::vector<double>& v) {
  std::ostringstream os;
  os << std::setprecision(9) << "[";
  for (size_t i = 0; i < v.size(); ++i) os << (i ? ", " : "") << v[i];
  os << "]";
  return os.str();
}

std::string json_vec(const Eigen::Vector3d& v) {
  std::ostringstream os;
  os << std::setprecision(17) << "[" << v(0) << ", " << v(1) << ", " << v(2) << "]";
  return os.str();
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  Utilities::logger.addSink(std::make_shared<Utilities::ConsoleSink>(Utilities::LogLevel::WARN));

  std::vector<Vector3r> V;
  std::vector<unsigned int> F;
  read_obj(o.surface, V, F);
  const unsigned int nv = static_cast<unsigned int>(V.size()), nf = static_cast<unsigned int>(F.size() / 3);

  // The counts tissuebench's build_constraints gives: one stretch constraint per
  // edge, one bending constraint per edge with two triangles.
  std::map<std::pair<unsigned, unsigned>, int> edge_faces;
  for (unsigned t = 0; t < nf; ++t)
    for (int k = 0; k < 3; ++k) {
      const unsigned a = F[3 * t + k], b = F[3 * t + (k + 1) % 3];
      ++edge_faces[{std::min(a, b), std::max(a, b)}];
    }
  size_t interior_edges = 0;
  for (const auto& e : edge_faces) interior_edges += e.second == 2;

  // Lumped masses (tb::pbd::lumped_surface_masses).
  std::vector<double> area(nv, 0.0);
  double total_area = 0, volume = 0;
  for (unsigned t = 0; t < nf; ++t) {
    const Eigen::Vector3d a = V[F[3 * t]].cast<double>(), b = V[F[3 * t + 1]].cast<double>(),
                          c = V[F[3 * t + 2]].cast<double>();
    const double A = 0.5 * (b - a).cross(c - a).norm();
    for (int k = 0; k < 3; ++k) area[F[3 * t + k]] += A / 3;
    total_area += A;
    volume += a.dot(b.cross(c)) / 6;  // enclosed volume, outward-oriented surface
  }
  const double total_mass = o.density * volume;

  // The library's model, solver and constraints.
  Simulation* sim = Simulation::getCurrent();
  SimulationModel* model = new SimulationModel();
  model->init();
  sim->setModel(model);
  Real gravity[3] = {0, 0, 0};
  sim->setVecValue<Real>(Simulation::GRAVITATION, gravity);
  TimeManager::getCurrent()->setTimeStepSize(static_cast<Real>(o.time_step));
  TimeStepController* solver = dynamic_cast<TimeStepController*>(sim->getTimeStep());
  if (!solver) throw std::runtime_error("the library's time step is not a TimeStepController");
  solver->setValue<unsigned int>(TimeStepController::NUM_SUB_STEPS, 1);
  solver->setValue<unsigned int>(TimeStepController::MAX_ITERATIONS, static_cast<unsigned int>(o.iterations));
  solver->setValue<unsigned int>(TimeStepController::MAX_ITERATIONS_V, 0);
  solver->setValue<int>(TimeStepController::VELOCITY_UPDATE_METHOD, 0);  // first order: v = (x - x_old) / dt

  TriangleModel::ParticleMesh::UVIndices uv_indices;
  TriangleModel::ParticleMesh::UVs uvs;
  model->addTriangleModel(nv, nf, V.data(), F.data(), uv_indices, uvs);
  ParticleData& pd = model->getParticles();
  size_t fixed = 0;
  for (unsigned i = 0; i < nv; ++i) {
    const Eigen::Vector3d x = V[i].cast<double>();
    const bool clamped = (x.array() >= o.support_min.array()).all() && (x.array() <= o.support_max.array()).all();
    fixed += clamped;
    pd.setMass(i, clamped ? 0 : static_cast<Real>(area[i] * (total_mass / total_area)));
  }
  TriangleModel* tm = model->getTriangleModels()[0];
  const Real k = static_cast<Real>(o.stiffness);
  model->addClothConstraints(tm, 1, k, 0, 0, 0, 0, 0, false, false);  // 1: a DistanceConstraint per edge
  model->addBendingConstraints(tm, 1, k);                             // 1: a DihedralConstraint per interior edge
  size_t distance = 0, dihedral = 0, other = 0;
  for (Constraint* c : model->getConstraints()) {
    if (c->getTypeId() == DistanceConstraint::TYPE_ID)
      ++distance;
    else if (c->getTypeId() == DihedralConstraint::TYPE_ID)
      ++dihedral;
    else
      ++other;
  }
  model->initConstraintGroups();  // the library's colouring (else done in the first frame)
  const auto& groups = model->getConstraintGroups();
  size_t largest_group = 0, smallest_group = groups.empty() ? 0 : groups[0].size(), parallel_groups = 0;
  for (const auto& g : groups) {
    largest_group = std::max(largest_group, g.size());
    smallest_group = std::min(smallest_group, g.size());
    parallel_groups += g.size() > MIN_PARALLEL_SIZE;
  }

  // The loaded vertex: the nearest to the load point, the first on ties (Eigen's minCoeff, as tissuebench).
  unsigned load = 0;
  double best = INFINITY;
  for (unsigned i = 0; i < nv; ++i) {
    const double d = (V[i].cast<double>() - o.load_point).squaredNorm();
    if (d < best) best = d, load = i;
  }

  std::vector<double> frame_ms, step_ms;
  frame_ms.reserve(static_cast<size_t>(o.frames));
  step_ms.reserve(static_cast<size_t>(o.frames));
  using Clock = std::chrono::steady_clock;
  using Ms = std::chrono::duration<double, std::milli>;
  const auto run_start = Clock::now();
  for (int frame = 0; frame < o.frames; ++frame) {
    // The library's own timers (Utils/Timing.h: the step and its position projection), from the first timed frame.
    if (frame == o.ramp) Utilities::Timing::reset();
    const double scale = frame < o.ramp ? static_cast<double>(frame + 1) / o.ramp : 1.0;
    const auto t0 = Clock::now();
    // Eq. (31): the loaded vertex's velocity, then damping of all, as tissuebench's Solver::step.
    pd.getVelocity(load) += (static_cast<Real>(o.time_step) * pd.getInvMass(load)) * (scale * o.force).cast<Real>();
    const Real keep = static_cast<Real>(1 - o.damping);
    for (unsigned i = 0; i < nv; ++i) pd.getVelocity(i) *= keep;
    const auto t1 = Clock::now();
    solver->step(*model);
    const auto t2 = Clock::now();
    frame_ms.push_back(Ms(t2 - t0).count());
    step_ms.push_back(Ms(t2 - t1).count());
    for (unsigned i = 0; i < nv; ++i)
      if (!pd.getPosition(i).allFinite()) throw std::runtime_error("diverged at frame " + std::to_string(frame));
  }
  const double run_s = std::chrono::duration<double>(Clock::now() - run_start).count();

  const std::vector<double> after(frame_ms.begin() + o.ramp, frame_ms.end());
  const std::vector<double> step_after(step_ms.begin() + o.ramp, step_ms.end());
  double max_u = 0;
  for (unsigned i = 0; i < nv; ++i)
    max_u = std::max(max_u, (pd.getPosition(i) - pd.getPosition0(i)).cast<double>().norm());
  const Eigen::Vector3d u_load = (pd.getPosition(load) - pd.getPosition0(load)).cast<double>();

  std::ostringstream timers;
  timers << std::setprecision(9) << "{";
  {
    bool first = true;
    for (const auto& t : Utilities::Timing::m_averageTimes) {
      timers << (first ? "" : ", ") << "\"" << t.second.name << "\": " << t.second.totalTime / t.second.counter;
      first = false;
    }
  }
  timers << "}";

  std::ostringstream js;
  js << std::setprecision(9) << "{\n"
     << "  \"library\": \"InteractiveComputerGraphics/PositionBasedDynamics\",\n"
     << "  \"real\": \"" << (sizeof(Real) == 8 ? "double" : "float") << "\",\n"
     << "  \"omp_max_threads\": " << omp_get_max_threads() << ",\n"
     << "  \"surface\": \"" << o.surface << "\",\n"
     << "  \"vertices\": " << nv << ",\n  \"triangles\": " << nf << ",\n"
     << "  \"fixed_vertices\": " << fixed << ",\n"
     << "  \"total_mass_kg\": " << total_mass << ",\n"
     << "  \"edges\": " << edge_faces.size() << ",\n  \"interior_edges\": " << interior_edges << ",\n"
     << "  \"distance_constraints\": " << distance << ",\n  \"dihedral_constraints\": " << dihedral << ",\n"
     << "  \"other_constraints\": " << other << ",\n"
     << "  \"constraint_groups\": " << groups.size() << ",\n"
     << "  \"groups_swept_in_parallel\": " << parallel_groups << ",\n"
     << "  \"group_size_range\": [" << smallest_group << ", " << largest_group << "],\n"
     << "  \"iterations\": " << solver->getValue<unsigned int>(TimeStepController::MAX_ITERATIONS) << ",\n"
     << "  \"sub_steps\": " << solver->getValue<unsigned int>(TimeStepController::NUM_SUB_STEPS) << ",\n"
     << "  \"velocity_iterations\": " << solver->getValue<unsigned int>(TimeStepController::MAX_ITERATIONS_V) << ",\n"
     << "  \"time_step_s\": " << o.time_step << ",\n  \"damping\": " << o.damping << ",\n"
     << "  \"stiffness\": " << o.stiffness << ",\n"
     << "  \"force_N\": " << json_vec(o.force) << ",\n  \"ramp_frames\": " << o.ramp << ",\n"
     << "  \"frames\": " << o.frames << ",\n"
     << "  \"load_vertex\": " << load << ",\n  \"load_vertex_position\": " << json_vec(V[load].cast<double>()) << ",\n"
     << "  \"load_vertex_displacement_m\": " << json_vec(u_load) << ",\n"
     << "  \"max_displacement_m\": " << max_u << ",\n"
     << "  \"run_s\": " << run_s << ",\n"
     << "  \"frame_after_ramp\": {\"median_ms\": " << quantile(after, 0.5) << ", \"p95_ms\": " << quantile(after, 0.95)
     << ", \"count\": " << after.size() << "},\n"
     << "  \"library_step_after_ramp\": {\"median_ms\": " << quantile(step_after, 0.5)
     << ", \"p95_ms\": " << quantile(step_after, 0.95) << "},\n"
     << "  \"library_timers_after_ramp_mean_ms\": " << timers.str() << ",\n"
     << "  \"frame_ms\": " << json_array(frame_ms) << "\n}\n";
  if (o.out.empty()) {
    std::cout << js.str();
  } else {
    std::ofstream f(o.out);
    f << js.str();
    if (!f) throw std::runtime_error("cannot write " + o.out);
  }
  delete sim;
  delete model;
  return 0;
}
