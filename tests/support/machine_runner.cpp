// machine_runner.cpp — in-process Machine driver for tests (see machine_runner.hpp).
#include "machine_runner.hpp"

#include <cmath>
#include <sstream>

#include "make_blocks.hpp"
#include "test_paths.hpp"

namespace pcnc::test {

// The desktop mill with path tolerance 0 (the seed's contouring rule): the rt tests that want a
// tolerance set one.
MachineConfig default_machine_config() {
  MachineConfig c = load_config(default_config());
  c.motion.path_tolerance_mm = 0.0;
  return c;
}

MachineConfig five_axis_config() { return load_config(source_dir() + "/configs/desktop-5axis.toml"); }

std::vector<Block> long_line(const MachineConfig& c, double feed) {
  ProgramBuilder p(c, home(c));
  p.rapid({1.0, 12.5, 20.0});
  p.line({24.0, 12.5, 20.0}, feed);
  p.end();
  return p.blocks();
}

void run_to_line(MachineRunner& run, std::uint32_t line, double min_speed) {
  run.run_while([&](const Status& s) { return !(s.line == line && s.path_speed >= min_speed) && s.state != MachineState::kFault; },
                100000);
}

MachineRunner::MachineRunner(const MachineConfig& config) : cfg_(config), machine_(config) {
  CycleRecord r;
  r.state = machine_.status().state;
  r.cmd = machine_.status().commanded;
  r.act = machine_.status().actual;
  r.truth = machine_.true_position();
  records_.push_back(r);
}

void MachineRunner::start(const std::vector<Block>& program) {
  program_ = program;
  next_ = 0;
  send(CommandKind::kProgramStart, 0.0);
}

void MachineRunner::send(CommandKind kind, double value, int axis, double feed) {
  Command c;
  c.id = next_id_++;
  c.kind = kind;
  c.axis = static_cast<std::uint8_t>(axis);
  c.value = value;
  c.feed = feed;
  machine_.command(c);
}

void MachineRunner::cycle() {
  while (feeding_ && next_ < program_.size() && ring_.try_push(program_[next_])) ++next_;
  machine_.cycle(ring_);
  const Status& s = machine_.status();
  CycleRecord r;
  r.state = s.state;
  r.line = s.line;
  r.seq = s.block_seq;
  r.cmd = s.commanded;
  r.act = s.actual;
  r.ferr = s.following_error;
  r.truth = machine_.true_position();
  r.speed = s.path_speed;
  r.blend = machine_.blending();
  records_.push_back(r);
}

void MachineRunner::run(std::size_t cycles) {
  for (std::size_t i = 0; i < cycles; ++i) cycle();
}

std::size_t MachineRunner::run_until_done(std::size_t max_cycles) {
  return run_while(
      [](const Status& s) {
        return !(s.program_done || s.state == MachineState::kFault || s.state == MachineState::kEstop ||
                 s.state == MachineState::kHostLost);
      },
      max_cycles);
}

std::size_t MachineRunner::run_while(const std::function<bool(const Status&)>& pred, std::size_t max_cycles) {
  std::size_t n = 0;
  while (n < max_cycles && pred(machine_.status())) {
    cycle();
    ++n;
  }
  return n;
}

std::string MachineRunner::check_setpoint_limits(double accel_scale) const {
  const double dt = cfg_.cycle_period_s();
  std::ostringstream os;
  for (std::size_t k = 1; k < records_.size(); ++k) {
    for (int i = 0; i < kAxes; ++i) {
      const AxisConfig& a = cfg_.axes[i];
      const double x = records_[k].cmd[i];
      if (x < a.travel_min_mm - 1e-9 || x > a.travel_max_mm + 1e-9) {
        os << "cycle " << k << ": " << axis_name(i) << " setpoint " << x << " outside the travel";
        return os.str();
      }
      const double v = (x - records_[k - 1].cmd[i]) / dt;
      if (std::abs(v) > a.max_velocity_mm_s * (1.0 + 1e-9) + 1e-9) {
        os << "cycle " << k << ": " << axis_name(i) << " velocity " << v << " > " << a.max_velocity_mm_s;
        return os.str();
      }
      if (k >= 2) {
        const double acc = (x - 2.0 * records_[k - 1].cmd[i] + records_[k - 2].cmd[i]) / (dt * dt);
        const double lim = a.max_accel_mm_s2 * accel_scale;
        if (std::abs(acc) > lim * (1.0 + 1e-6) + 1e-3) {
          os << "cycle " << k << " (line " << records_[k].line << "): " << axis_name(i) << " acceleration " << acc
             << " > " << lim;
          return os.str();
        }
      }
    }
  }
  return "";
}

}  // namespace pcnc::test
