#include "mgelastic/sim/grid_stepper.hpp"

#include <type_traits>

#include "mgelastic/core/error.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/grid/backward_euler.hpp"
#include "mgelastic/grid/corotated_dynamics.hpp"
#include "mgelastic/grid/corotated_multigrid.hpp"

namespace mgelastic::sim {
namespace {

using VectorField = std::function<grid::Vec<3>(const grid::Vec<3>&)>;

// Plain cycles without a new smallest residual before a solve counts as stalled at round-off
// (a converging solve, however slowly, lowers it every cycle): float round-off in single
// precision, x's own rounding (~eps |A| |x|) in double and mixed precision, where a tolerance
// below it ran every cycle up to solver.max_vcycles (cantilever_tip_force at 256 cells,
// tolerance 1e-11, plain cycles: all 200 allowed, 7.7 s; now 21 cycles, 1.3 s). Fixed cycle
// counts (time.vcycles_per_step) run every cycle.
constexpr int kStallCycles = 3;

double reduction(const std::vector<double>& residuals) {
  return residuals.front() > 0 ? residuals.back() / residuals.front() : 0.0;
}

grid::MultigridOptions multigrid_options(const scene::Scene& s) {
  grid::MultigridOptions options;
  options.boundary_sweeps = s.boundary_sweeps;
  options.band_layers = s.band_layers;
  options.local_corrections = s.local_corrections;
  options.band_sweep_order = grid::band_sweep_order(s.smoother_order);
  options.cycle = s.cycle == "W" ? grid::CycleType::W : grid::CycleType::V;
  // "single": the float finest level holds the solution (no double copy); "float": mixed.
  options.mixed_precision = s.precision != "single";
  return options;
}

grid::CorotatedOptions corotated_options(const scene::Scene& s) {
  grid::CorotatedOptions options;
  options.rotation_update_every = s.time.rotation_update_every;
  options.smoother = s.corotated_smoother == "distributive" ? grid::CorotatedSmoother::DISTRIBUTIVE
                                                            : grid::CorotatedSmoother::BOX;
  return options;
}

grid::TimeStepOptions time_step_options(const scene::Scene& s) {
  return {.dt = s.time.dt / s.time.substeps,
          .density = s.density,
          .damping = s.time.damping,
          .mass_damping = s.time.mass_damping,
          .vcycles_per_step = s.time.vcycles_per_step,
          .tolerance = s.tolerance,
          .max_vcycles = s.max_vcycles,
          .accelerate = s.accelerate};
}

StepStats linear_stats(const grid::SolveReport& r) {
  return {.cycles = r.cycles(),
          .relative_residual = reduction(r.residuals),
          .converged = r.converged,
          .stalled = r.stalled,
          .seconds = r.seconds};
}

StepStats corotated_stats(const grid::CorotatedReport& r) {
  return {.cycles = r.cycles(),
          .relative_residual = reduction(r.nonlinear),
          .quasi_linear_reduction = reduction(r.quasi_linear),
          .quasi_linear_residual = r.quasi_linear.back(),
          .converged = r.converged,
          .seconds = r.seconds};
}

// Carried state beyond the unknowns. Velocities of a dynamic run: "grid.v0".."grid.v2", zero
// outside the lattice's live chunks (grid::allocate_step_state), which are not read.
void add_velocity(io::Checkpoint& c, const std::array<grid::FieldArray<double>, 3>& v,
                  const grid::LiveChunks& live) {
  const auto ranges = grid::live_ranges(live, v[0].size());
  for (std::size_t f = 0; f < v.size(); ++f)
    c.add_nonzero_runs<double>("grid.v" + std::to_string(f), v[f], ranges);
}

// Array `name` of checkpoint c as a field of `size` values (Checkpoint::get_into checks the
// length; lattice fields are stored as their non-zero runs, and the fresh field's zero pages are
// only read).
grid::FieldArray<double> stored_field(const io::Checkpoint& c, const std::string& name,
                                      std::size_t size) {
  grid::FieldArray<double> field(size);
  c.get_into<double>(name, field);
  return field;
}

void restore_velocity(const io::Checkpoint& c, std::array<grid::FieldArray<double>, 3>& v) {
  for (std::size_t f = 0; f < v.size(); ++f)
    v[f] = stored_field(c, "grid.v" + std::to_string(f), v[f].size());
}

// Co-rotated model (CorotatedCarriedState): the finest rotations the frozen rows were built from
// ("grid.rotations"), the cycles since their refresh ("grid.corotated_cycles"), the Newton step's
// recycled corrections ("grid.recycled0", ...).
void add_corotated(io::Checkpoint& c, const grid::CorotatedMultigrid<3>& solver) {
  const grid::CorotatedCarriedState<3> state = solver.carried_state();
  c.add<double>("grid.rotations", state.rotations);
  const std::vector<std::int64_t> counters{state.cycles_since_refresh,
                                           static_cast<std::int64_t>(state.recycled.size())};
  c.add<std::int64_t>("grid.corotated_cycles", counters);
  for (std::size_t i = 0; i < state.recycled.size(); ++i)
    c.add<double>("grid.recycled" + std::to_string(i),
                  std::span<const double>(state.recycled[i].data(), state.recycled[i].size()));
}

// The solution level's right-hand side in a start state (GridStepper::save_start).
std::string start_rhs_name(std::size_t field) {
  return "grid.start_b" + std::to_string(field);
}

void restore_corotated(const io::Checkpoint& c, grid::CorotatedMultigrid<3>& solver) {
  grid::CorotatedCarriedState<3> state;
  state.rotations = c.get<double>("grid.rotations");
  const auto counters = c.get<std::int64_t>("grid.corotated_cycles", 2);
  state.cycles_since_refresh = static_cast<int>(counters[0]);
  for (std::int64_t i = 0; i < counters[1]; ++i) {
    const auto z = c.get<double>("grid.recycled" + std::to_string(i));
    state.recycled.emplace_back(Eigen::Map<const Eigen::VectorXd>(z.data(), z.size()));
  }
  try {
    solver.restore_carried_state(state);
  } catch (const Error& e) {
    throw Error(e.reason(), ErrorContext{.file = c.source});
  }
}

}  // namespace

// The model x integrator choice. `solve(time, dirichlet)`: quasistatic, the equilibrium at
// `time`; dynamic, one step ending at `time`. An empty `dirichlet` keeps the current one.
class GridStepper::Solver {
 public:
  virtual ~Solver() = default;
  virtual StepStats solve(double time, const VectorField& dirichlet) = 0;
  virtual double time() const { return 0; }
  virtual void set_time(double) {}
  virtual void set_velocity(const Eigen::Vector3d&) {}
  virtual const std::array<grid::FieldArray<double>, 3>* face_velocity() const { return nullptr; }
  virtual double inertia() const { return 0; }
  virtual void save_carried(io::Checkpoint&) const {}
  virtual void restore_carried(const io::Checkpoint&) {}
  // The linear hierarchy's local corrections (Multigrid::local_correction_state).
  virtual void save_local_corrections(io::Checkpoint&) const {}
  virtual void restore_local_corrections(const io::Checkpoint&) {}
  virtual bool single_precision() const { return false; }
  virtual std::size_t bytes() const { return 0; }
  virtual int levels() const = 0;
  virtual std::size_t unknowns() const = 0;
  virtual const grid::PhaseSeconds& phase_seconds() const = 0;
  // The finest level and its unknowns (fields and checkpoints).
  virtual const grid::Level<3, double>* level_double() const { return nullptr; }
  virtual const grid::Level<3, float>* level_float() const { return nullptr; }
  // The finest lattice's live chunks (grid/live_chunks.hpp): lattice fields are zero outside.
  virtual const grid::LiveChunks& live_chunks() const = 0;
  // The linear model's double solution level (reactions); null for the co-rotated model.
  virtual const grid::Level<3, double>* linear_solution() const { return nullptr; }
  virtual double solution(int field, std::ptrdiff_t k) const = 0;
  // The finest unknowns in double (the solver's own arrays where it holds them in double).
  virtual const std::array<grid::FieldArray<double>, 4>& unknowns_state() const = 0;
  virtual void set_unknowns_state(const std::array<grid::FieldArray<double>, 4>& x) = 0;
  // The solution level's right-hand side (Multigrid::solution_level().b): a cancelled solve may
  // leave it half-way (FGMRES works on a cleared one, co-rotated load steps blend it).
  virtual const std::array<grid::FieldArray<double>, 4>& right_hand_side() const = 0;
  virtual void set_right_hand_side(const std::array<grid::FieldArray<double>, 4>& b) = 0;
  // Takes the problem's new loads in place (Multigrid::set_loads, CorotatedMultigrid::set_loads).
  virtual void set_loads(const grid::ElasticityProblem<3>& problem) = 0;
};

namespace {

// What every solver reads from its linear hierarchy (the co-rotated ones: the one they cycle on).
template <typename Scalar>
class HierarchySolver : public GridStepper::Solver {
 public:
  bool single_precision() const override { return std::is_same_v<Scalar, float>; }
  int levels() const override { return hierarchy().levels(); }
  std::size_t unknowns() const override { return hierarchy().unknowns(); }
  const grid::PhaseSeconds& phase_seconds() const override { return hierarchy().phase_seconds(); }
  const grid::Level<3, double>* level_double() const override {
    if constexpr (std::is_same_v<Scalar, double>) return &hierarchy().finest();
    return nullptr;
  }
  const grid::Level<3, float>* level_float() const override {
    if constexpr (std::is_same_v<Scalar, float>) return &hierarchy().finest();
    return nullptr;
  }
  const grid::LiveChunks& live_chunks() const override { return hierarchy().finest().live; }
  double solution(int field, std::ptrdiff_t k) const override {
    return hierarchy().solution(field, k);
  }
  const std::array<grid::FieldArray<double>, 4>& unknowns_state() const override {
    return hierarchy().solution_state();
  }
  void set_unknowns_state(const std::array<grid::FieldArray<double>, 4>& x) override {
    hierarchy().set_solution_state(x);
  }
  const std::array<grid::FieldArray<double>, 4>& right_hand_side() const override {
    if (!hierarchy().single_precision()) return hierarchy().solution_level().b;
    // Single precision: the float finest level holds b; a double copy made on request.
    const auto& b = hierarchy().finest().b;
    for (std::size_t f = 0; f < b.size(); ++f) m_single_rhs[f].assign(b[f].begin(), b[f].end());
    return m_single_rhs;
  }
  void save_local_corrections(io::Checkpoint& c) const override {
    const auto state = hierarchy().local_correction_state();
    c.add<std::int64_t>("grid.local_corrections", state.integers);
    c.add<double>("grid.local_correction_ratio", std::vector<double>{state.ratio_at_placement});
  }
  void restore_local_corrections(const io::Checkpoint& c) override {
    if (!c.has("grid.local_corrections")) return;  // written before local corrections
    typename grid::Multigrid<3, Scalar>::LocalCorrectionState state;
    state.integers = c.get<std::int64_t>("grid.local_corrections");
    state.ratio_at_placement = c.get<double>("grid.local_correction_ratio", 1)[0];
    try {
      hierarchy().restore_local_correction_state(state);
    } catch (const Error& e) {
      throw Error(e.reason(), ErrorContext{.file = c.source});
    }
  }
  void set_right_hand_side(const std::array<grid::FieldArray<double>, 4>& b) override {
    if (!hierarchy().single_precision()) {
      auto& solution = hierarchy().solution_level();
      grid::assign_live(solution.b, b, solution.live);
      return;
    }
    auto& finest = hierarchy().level(0).b;
    for (std::size_t f = 0; f < b.size(); ++f) finest[f].assign(b[f].begin(), b[f].end());
  }

 protected:
  virtual grid::Multigrid<3, Scalar>& hierarchy() = 0;
  const grid::Multigrid<3, Scalar>& hierarchy() const {
    return const_cast<HierarchySolver*>(this)->hierarchy();
  }

 private:
  mutable std::array<grid::FieldArray<double>, 4> m_single_rhs;  // right_hand_side() in single
};

template <typename Scalar>
class LinearStatic final : public HierarchySolver<Scalar> {
 public:
  LinearStatic(const scene::GridSetup& setup, const scene::Scene& s)
      : m_scene(s), m_mg(setup.problem, multigrid_options(s)) {}
  StepStats solve(double, const VectorField& dirichlet) override {
    if (dirichlet) m_mg.set_dirichlet_displacement(dirichlet);
    // Single precision has no double solution level for FGMRES (scene validation refuses an
    // explicit accelerate). Plain cycles stop where round-off stalls the residual; the
    // accelerated solve has its own rule (two restarts at the floor).
    if (m_scene.accelerate && !m_mg.single_precision())
      return linear_stats(m_mg.solve_accelerated(m_scene.tolerance, m_scene.max_vcycles));
    return linear_stats(m_mg.solve(m_scene.tolerance, m_scene.max_vcycles, kStallCycles));
  }
  std::size_t bytes() const override { return m_mg.bytes(); }
  // Reactions sum the double solution level's rows: none in single precision.
  const grid::Level<3, double>* linear_solution() const override {
    return m_mg.single_precision() ? nullptr : &m_mg.solution_level();
  }
  void set_loads(const grid::ElasticityProblem<3>& problem) override { m_mg.set_loads(problem); }

 protected:
  grid::Multigrid<3, Scalar>& hierarchy() override { return m_mg; }

 private:
  const scene::Scene& m_scene;
  grid::Multigrid<3, Scalar> m_mg;
};

// What both backward-Euler integrators share: the clock and the face velocities.
template <typename Integrator, typename Scalar>
class Dynamic : public HierarchySolver<Scalar> {
 public:
  double time() const override { return m_sim.time(); }
  void set_time(double t) override { m_sim.set_time(t); }
  void set_velocity(const Eigen::Vector3d& v0) override {
    m_sim.set_velocity([v0](const grid::Vec<3>&) { return v0; });
  }
  const std::array<grid::FieldArray<double>, 3>* face_velocity() const override {
    return &m_sim.velocity();
  }

 protected:
  template <typename... Args>
  explicit Dynamic(Args&&... args) : m_sim(std::forward<Args>(args)...) {}
  Integrator m_sim;
};

template <typename Scalar>
class LinearDynamic final : public Dynamic<grid::BackwardEuler<3, Scalar>, Scalar> {
 public:
  LinearDynamic(const scene::GridSetup& setup, const scene::Scene& s)
      : Dynamic<grid::BackwardEuler<3, Scalar>, Scalar>(setup.problem, time_step_options(s),
                                                        multigrid_options(s)) {}
  StepStats solve(double, const VectorField& dirichlet) override {
    return linear_stats(this->m_sim.step(dirichlet));
  }
  double inertia() const override { return this->m_sim.inertia(); }
  void set_loads(const grid::ElasticityProblem<3>& problem) override {
    this->m_sim.set_loads(problem);
  }
  void save_carried(io::Checkpoint& c) const override {
    add_velocity(c, this->m_sim.velocity(), this->live_chunks());
  }
  void restore_carried(const io::Checkpoint& c) override {
    restore_velocity(c, this->m_sim.velocity());
    this->m_sim.set_time(c.time);
  }
  std::size_t bytes() const override { return this->m_sim.multigrid().bytes(); }
  const grid::Level<3, double>* linear_solution() const override {
    return &this->m_sim.multigrid().solution_level();
  }

 protected:
  grid::Multigrid<3, Scalar>& hierarchy() override { return this->m_sim.multigrid(); }
};

class CorotatedStatic final : public HierarchySolver<double> {
 public:
  CorotatedStatic(const scene::GridSetup& setup, const scene::Scene& s)
      : m_scene(s), m_solver(setup.problem, multigrid_options(s), corotated_options(s)) {}
  StepStats solve(double, const VectorField& dirichlet) override {
    if (dirichlet) m_solver.set_dirichlet_displacement(dirichlet);
    return corotated_stats(m_solver.solve_with_load_steps(m_scene.tolerance, m_scene.max_vcycles));
  }
  void set_loads(const grid::ElasticityProblem<3>& problem) override {
    m_solver.set_loads(problem);
  }
  void save_carried(io::Checkpoint& c) const override { add_corotated(c, m_solver); }
  void restore_carried(const io::Checkpoint& c) override { restore_corotated(c, m_solver); }

 protected:
  grid::Multigrid<3, double>& hierarchy() override { return m_solver.linear_hierarchy(); }

 private:
  const scene::Scene& m_scene;
  grid::CorotatedMultigrid<3> m_solver;
};

class CorotatedDynamic final : public Dynamic<grid::CorotatedBackwardEuler<3>, double> {
 public:
  CorotatedDynamic(const scene::GridSetup& setup, const scene::Scene& s)
      : Dynamic(setup.problem, stepping(s), multigrid_options(s), corotated_options(s)) {}
  StepStats solve(double, const VectorField& dirichlet) override {
    return corotated_stats(m_sim.step(dirichlet));
  }
  void set_loads(const grid::ElasticityProblem<3>& problem) override { m_sim.set_loads(problem); }
  void save_carried(io::Checkpoint& c) const override {
    add_velocity(c, m_sim.velocity(), live_chunks());
    add_corotated(c, m_sim.multigrid());
  }
  void restore_carried(const io::Checkpoint& c) override {
    restore_velocity(c, m_sim.velocity());
    m_sim.set_time(c.time);
    restore_corotated(c, m_sim.multigrid());
  }

 protected:
  grid::Multigrid<3, double>& hierarchy() override { return m_sim.multigrid().linear_hierarchy(); }

 private:
  // The co-rotated integrator takes no FGMRES acceleration.
  static grid::TimeStepOptions stepping(const scene::Scene& s) {
    grid::TimeStepOptions o = time_step_options(s);
    o.accelerate = false;
    return o;
  }
};

std::unique_ptr<GridStepper::Solver> make_solver(const scene::GridSetup& setup,
                                                 const scene::Scene& s) {
  const bool corotated = s.material_model == "corotated";
  const bool single = s.precision != "double";
  if (s.time.quasistatic) {
    if (corotated) return std::make_unique<CorotatedStatic>(setup, s);
    if (single) return std::make_unique<LinearStatic<float>>(setup, s);
    return std::make_unique<LinearStatic<double>>(setup, s);
  }
  if (corotated) return std::make_unique<CorotatedDynamic>(setup, s);
  if (single) return std::make_unique<LinearDynamic<float>>(setup, s);
  return std::make_unique<LinearDynamic<double>>(setup, s);
}

}  // namespace

struct GridStepper::Cache {
  std::optional<grid::NodeDisplacement> displacement;
  std::optional<std::vector<double>> velocity, pressure, von_mises;
  std::optional<std::vector<std::uint8_t>> cell_types;
  std::optional<grid::PointRows> surface;
};

GridStepper::GridStepper(const scene::Scene& scene) : m_scene(&scene), m_cache(new Cache) {
  if (!scene.time.quasistatic && scene.time.integrator != "implicit_euler")
    throw Error("the grid engine integrates with implicit_euler (backward Euler, Sec. 8) only",
                ErrorContext{.file = scene.file, .pointer = "/time/integrator"});
  Timer timer;
  m_setup = scene::build_grid_setup(scene);
  m_setup_seconds = timer.seconds();
  timer.restart();
  m_solver = make_solver(m_setup, scene);
  m_hierarchy_seconds = timer.seconds();
  m_step_dt = scene.time.dt / scene.time.substeps;
  const Eigen::Vector3d v0 = scene.initial_velocity;
  if (!scene.time.quasistatic && v0.squaredNorm() > 0) m_solver->set_velocity(v0);
}

GridStepper::~GridStepper() = default;

FrameStats GridStepper::advance_frame(int frame, double& attempt_time) {
  const scene::Scene& s = *m_scene;
  if (m_loads_changed) reload_loads();
  FrameStats stats;
  stats.frame = frame;
  // Quasistatic: frame k shows the equilibrium at time (k + 1) dt (after the first interval),
  // one solve. Dynamic: `substeps` steps from the integrator's clock.
  const int steps = s.time.quasistatic ? 1 : s.time.substeps;
  for (int step = 0; step < steps; ++step) {
    const double time = s.time.quasistatic ? (frame + 1) * s.time.dt : m_solver->time() + m_step_dt;
    attempt_time = time;
    // Keyframed regions move to the solve's time.
    const VectorField dirichlet =
        m_setup.animated() ? scene::dirichlet_displacement(m_setup, time) : VectorField{};
    // The whole step counts as solve time, not only the cycles: a dynamic step's right-hand
    // side, warm start and velocity update cost a fifth of its cycles at 256 cells.
    Timer timer;
    const StepStats r = m_solver->solve(time, dirichlet);
    invalidate();
    stats.step_stats.push_back(r);
    stats.cycles += r.cycles;
    stats.solve_seconds += timer.seconds();
    stats.worst_residual = std::max(stats.worst_residual, r.relative_residual);
    stats.converged = stats.converged && r.converged;
    m_time = s.time.quasistatic ? time : m_solver->time();
  }
  stats.steps = steps;
  stats.time = m_time;
  return stats;
}

double GridStepper::time() const {
  return m_time;
}

void GridStepper::save(io::Checkpoint& c, const std::vector<io::NamedArray>& attachments) const {
  // Straight from the solver's arrays: a run snapshots its state after every frame (the last
  // good state a failed frame saves, run_checkpoints.hpp).
  const auto& x = m_solver->unknowns_state();
  const auto ranges = grid::live_ranges(m_solver->live_chunks(), x[0].size());
  for (std::size_t f = 0; f < x.size(); ++f)
    c.add_nonzero_runs<double>("grid.x" + std::to_string(f), x[f], ranges);
  c.arrays.insert(c.arrays.end(), attachments.begin(), attachments.end());
  m_solver->save_carried(c);
  m_solver->save_local_corrections(c);
}

void GridStepper::restore(const io::Checkpoint& c) {
  const auto& now = m_solver->unknowns_state();
  std::array<grid::FieldArray<double>, 4> x;
  for (std::size_t f = 0; f < x.size(); ++f)
    x[f] = stored_field(c, "grid.x" + std::to_string(f), now[f].size());
  m_solver->set_unknowns_state(x);
  m_solver->restore_carried(c);
  m_solver->restore_local_corrections(c);
  m_time = c.time;
  invalidate();
}

void GridStepper::set_region_pose(std::size_t region, const Eigen::Vector3d& translate,
                                  const Eigen::Quaterniond& rotate) {
  require(region < m_setup.regions.size(), "region",
          "no constraint region " + std::to_string(region) + " (the scene has " +
              std::to_string(m_setup.regions.size()) + ")");
  auto& motion = m_setup.regions[region].motion;
  motion = scene::KeyframedMotion(motion.pivot(), {scene::RigidKeyframe{0.0, translate, rotate}});
}

// The loads live in the finest level's right-hand side and in its boundary rows (constants and
// traction rules), for the co-rotated model also in its finest rotated rows' constants: every
// model replaces them in place (Multigrid::set_loads, CorotatedMultigrid::set_loads), no
// hierarchy build.
void GridStepper::reload_loads() {
  scene::set_surface_loads(*m_scene, m_setup);
  m_loads_changed = false;
  Timer timer;
  m_solver->set_loads(m_setup.problem);
  m_load_update_seconds = timer.seconds();
}

void GridStepper::save_start(io::Checkpoint& c) {
  if (m_loads_changed) reload_loads();
  save(c, {});
  const auto& b = m_solver->right_hand_side();
  const auto ranges = grid::live_ranges(m_solver->live_chunks(), b[0].size());
  for (std::size_t f = 0; f < b.size(); ++f)
    c.add_nonzero_runs<double>(start_rhs_name(f), b[f], ranges);
}

void GridStepper::return_to_start(const io::Checkpoint& start) {
  // The right-hand side first: the co-rotated model takes the current load as the equilibrium
  // its load stepping starts from (CorotatedMultigrid::restore_carried_state).
  const auto& now = m_solver->right_hand_side();
  std::array<grid::FieldArray<double>, 4> b;
  for (std::size_t f = 0; f < b.size(); ++f)
    b[f] = stored_field(start, start_rhs_name(f), now[f].size());
  m_solver->set_right_hand_side(b);
  restore(start);
}

void GridStepper::invalidate() {
  *m_cache = Cache{};
}

bool GridStepper::single_precision() const {
  return m_solver->single_precision();
}

const grid::NodeDisplacement& GridStepper::displacement() const {
  if (!m_cache->displacement) {
    const auto value = [&](int f, std::ptrdiff_t k) { return m_solver->solution(f, k); };
    if (const auto* level = m_solver->level_float())
      m_cache->displacement = grid::node_displacement<float>(*level, value);
    else
      m_cache->displacement = grid::node_displacement<double>(*m_solver->level_double(), value);
  }
  return *m_cache->displacement;
}

const std::vector<double>& GridStepper::velocity() const {
  if (!m_cache->velocity) {
    const auto* v = m_solver->face_velocity();
    if (!v) {
      m_cache->velocity = std::vector<double>(displacement().values.size(), 0.0);
    } else {
      const auto value = [&](int f, std::ptrdiff_t k) { return (*v)[f][k]; };
      if (const auto* level = m_solver->level_float())
        m_cache->velocity = grid::node_displacement<float>(*level, value).values;
      else
        m_cache->velocity =
            grid::node_displacement<double>(*m_solver->level_double(), value).values;
    }
  }
  return *m_cache->velocity;
}

namespace {

// Pressure -trace(sigma) / 3 in Pa of an interior cell. The solver's p is the paper's scaled
// pressure (sigma = mu (grad u + grad u^T) - mu p I, p = -(lambda / mu) div u), so the mean
// stress needs mu p and the divergence of the cell's faces.
template <typename Scalar>
double cell_pressure(const grid::Level<3, Scalar>& level, const GridStepper::Solver& solver,
                     std::ptrdiff_t cell, double mu) {
  double divergence = 0;
  for (int i = 0; i < 3; ++i)
    divergence += solver.solution(i, cell + level.lattice.stride(i)) - solver.solution(i, cell);
  divergence /= level.lattice.h;
  return mu * solver.solution(3, cell) - 2.0 / 3.0 * mu * divergence;
}

template <typename Scalar>
void cell_fields(const grid::Level<3, Scalar>& level, const GridStepper::Solver& solver, double mu,
                 std::vector<double>& von_mises, std::vector<double>& pressure,
                 std::vector<std::uint8_t>& types) {
  const auto& n = level.lattice.cells;
  std::size_t c = 0;
  for (int k = 1; k <= n[2]; ++k)
    for (int j = 1; j <= n[1]; ++j)
      for (int i = 1; i <= n[0]; ++i, ++c) {
        const std::ptrdiff_t cell = level.lattice.index(grid::IVec<3>(i, j, k));
        const bool interior = level.cells[cell] == grid::CellType::INTERIOR;
        types.push_back(static_cast<std::uint8_t>(level.cells[cell]));
        pressure.push_back(interior ? cell_pressure(level, solver, cell, mu) : 0.0);
        if (level.cells[cell] == grid::CellType::EXTERIOR) von_mises[c] = 0.0;
      }
}

}  // namespace

const std::vector<double>& GridStepper::von_mises() const {
  if (!m_cache->von_mises) {
    const grid::Material material{m_scene->youngs_modulus, m_scene->poisson_ratio};
    std::vector<double> stress = grid::von_mises_stress(displacement(), material);
    std::vector<double> pressure;
    std::vector<std::uint8_t> types;
    if (const auto* level = m_solver->level_float())
      cell_fields(*level, *m_solver, material.mu(), stress, pressure, types);
    else
      cell_fields(*m_solver->level_double(), *m_solver, material.mu(), stress, pressure, types);
    m_cache->von_mises = std::move(stress);
    m_cache->pressure = std::move(pressure);
    m_cache->cell_types = std::move(types);
  }
  return *m_cache->von_mises;
}

const std::vector<double>& GridStepper::pressure() const {
  von_mises();
  return *m_cache->pressure;
}

const std::vector<std::uint8_t>& GridStepper::cell_types() const {
  von_mises();
  return *m_cache->cell_types;
}

const grid::PointRows& GridStepper::surface_vertices() const {
  if (!m_cache->surface) {
    const auto method = m_scene->surface_interpolation == "trilinear"
                            ? grid::SurfaceInterpolation::TRILINEAR
                            : grid::SurfaceInterpolation::TRICUBIC;
    grid::PointRows deformed;
    grid::displace_points(displacement(), method, m_setup.surface.vertices, deformed);
    m_cache->surface = std::move(deformed);
  }
  return *m_cache->surface;
}

namespace {
template <typename F>
auto with_level(const GridStepper::Solver& solver, F f) {
  if (const auto* level = solver.level_float()) return f(level->lattice);
  return f(solver.level_double()->lattice);
}
}  // namespace

const grid::Level<3, double>* GridStepper::linear_solution() const {
  return m_solver->linear_solution();
}

const grid::Level<3, double>* GridStepper::corotated_solution() const {
  return m_scene->material_model == "corotated" ? m_solver->level_double() : nullptr;
}

Eigen::Vector3i GridStepper::cells() const {
  return with_level(*m_solver, [](const auto& lattice) {
    return Eigen::Vector3i(lattice.cells[0], lattice.cells[1], lattice.cells[2]);
  });
}

double GridStepper::spacing() const {
  return with_level(*m_solver, [](const auto& lattice) { return double(lattice.h); });
}

Eigen::Vector3d GridStepper::origin() const {
  return with_level(*m_solver, [](const auto& lattice) {
    return Eigen::Vector3d(lattice.origin[0], lattice.origin[1], lattice.origin[2]);
  });
}

int GridStepper::levels() const {
  return m_solver->levels();
}
std::size_t GridStepper::unknowns() const {
  return m_solver->unknowns();
}
std::size_t GridStepper::bytes() const {
  return m_solver->bytes();
}
const grid::PhaseSeconds& GridStepper::phase_seconds() const {
  return m_solver->phase_seconds();
}
double GridStepper::inertia() const {
  return m_solver->inertia();
}

}  // namespace mgelastic::sim
