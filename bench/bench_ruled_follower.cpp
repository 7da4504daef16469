// bench_ruled_follower.cpp — issue 17, item 2's figures for the rt's evaluator of a ruled
// piece (rt/motion/ruled_follower.hpp) on the XYZAC machine of configs/desktop-5axis.toml
// (never pass/fail). Three passes of the seed's example scaled to the desktop mill (X = -10,
// 0, 10 mm along Y in program coordinates, G54 from the config; ball R 1 mm, lead 0), set
// points every 0.5, 1 or 2 mm, each pass one ruled piece (split into blocks of at most
// kMaxRuledSegments segments, the leftover carried across the joins), followed from rest to
// rest at the piece's acceleration. Printed:
//  - cost per cycle: RuledFollower::step (speed, Taylor step with chord correction, pose,
//    analytic derivatives, inverse kinematics, joint velocity and acceleration feed-forward)
//    and ruled_sample_at alone (pose + derivatives + inverse kinematics + Jacobian rates), the
//    fastest of 7 runs over every cycle of the passes (the goal: under 10 us; the seed
//    paper took 8.14 ms per sample);
//  - the feed error: chord per cycle against the programmed feed times the period at the
//    constant-feed stretches (and at the block joins, the rest of one block plus the carry);
//  - the swept tool axis's deviation from the intended ruled surface (the exact tip curve and
//    axis of the pass, from the surface): the pose the follower's joints command (forward
//    kinematics of q), the distance of the tip and of the point --height mm up the axis from
//    the nearest ruling of the intended surface, against G1 moves through the same set points
//    with the joints A and C interpolated linearly (the tip on the chord).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "config/config.hpp"
#include "geometry/kinematics.hpp"
#include "geometry/ruled_model.hpp"
#include "geometry/ruled_passes.hpp"
#include "ipc/block_ruled.hpp"
#include "motion/ruled_follower.hpp"

using namespace pcnc;

namespace {

using Clock = std::chrono::steady_clock;

struct PassLine {
  BSplineSurface surface;
  double u = 0.0;
  Vec3 offset{};  // program to workpiece coordinates (G54)
  ToolPose at(double v) const {
    const SurfaceEval e = surface_eval(surface, u, v);
    const PassPoint p = pass_point(e, e.sv, 1.0, 0.0);
    return {p.tip + offset, p.axis};
  }
};

// The smallest distance of x from the intended rulings over v in [lo, hi]: a scan, then golden
// section around the best point of the scan.
double ruling_distance(const PassLine& pass, const Vec3& x, double lo, double hi) {
  auto f = [&](double v) {
    const ToolPose r = pass.at(v);
    const Vec3 q = x - r.tip;
    return norm(q - dot(q, r.axis) * r.axis);
  };
  const int n = 8;
  int best = 0;
  double fb = 1e300;
  for (int i = 0; i <= n; ++i) {
    const double fx = f(lo + (hi - lo) * i / n);
    if (fx < fb) fb = fx, best = i;
  }
  double a = lo + (hi - lo) * std::max(0, best - 1) / n, b = lo + (hi - lo) * std::min(n, best + 1) / n;
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double m1 = b - g * (b - a), m2 = a + g * (b - a), f1 = f(m1), f2 = f(m2);
  for (int it = 0; it < 50; ++it) {
    if (f1 < f2) {
      b = m2, m2 = m1, f2 = f1, m1 = b - g * (b - a), f1 = f(m1);
    } else {
      a = m1, m1 = m2, f1 = f2, m2 = a + g * (b - a), f2 = f(m2);
    }
  }
  return std::min(fb, f(0.5 * (a + b)));
}

struct Deviation {
  double tip = 0.0, high = 0.0;
  long samples = 0;
  void add(const PassLine& pass, const ToolPose& p, double lo, double hi, double height) {
    tip = std::max(tip, ruling_distance(pass, p.tip, lo, hi));
    high = std::max(high, ruling_distance(pass, p.tip + height * p.axis, lo, hi));
    ++samples;
  }
};

struct FeedError {
  double max = 0.0, ss = 0.0, join_max = 0.0;
  long n = 0, joins = 0;
};

struct Piece {
  std::vector<RuledGeometry> blocks;
  std::vector<double> vs;  // the intended surface's v at each set point
  std::vector<ToolPose> set;
};

Piece make_piece(const PassLine& pass, double spacing, double feed, double accel) {
  Piece pc;
  const int n = static_cast<int>(std::ceil(25.0 / spacing - 1e-9));
  std::vector<Vec3> tips, axes;
  for (int i = 0; i <= n; ++i) {
    const double v = static_cast<double>(i) / n;
    const ToolPose p = pass.at(v);
    pc.vs.push_back(v);
    pc.set.push_back(p);
    tips.push_back(p.tip);
    axes.push_back(p.axis);
  }
  const RuledModelResult m = ruled_model_through(tips, axes, RulingForm::kVector);
  if (!m.error.empty()) std::fprintf(stderr, "model: %s\n", m.error.c_str());
  const std::vector<RuledModel> parts = split_for_blocks(m.model);
  pc.blocks.resize(parts.size());
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::string err = to_geometry(parts[i], feed, accel, i == 0 ? 0.0 : feed,
                                        i + 1 == parts.size() ? 0.0 : feed, pc.blocks[i]);
    if (!err.empty()) std::fprintf(stderr, "block: %s\n", err.c_str());
  }
  return pc;
}

// Follows the piece; `each(sample, first_segment_of_block, block)` sees every cycle's sample.
template <class Each>
long follow(const Piece& pc, const Kinematics& kin, double period, Each each, FeedError* fe) {
  RuledFollower f;
  const Joints q0 = inverse(kin, pc.set[0], Joints{});
  long cycles = 0;
  int seg0 = 0;
  for (std::size_t b = 0; b < pc.blocks.size(); ++b) {
    const RuledGeometry& g = pc.blocks[b];
    if (b == 0) {
      f.start(g, kin, RotaryTravel{}, q0);
    } else {
      const double before = f.sample().chord, carry = f.leftover();
      f.start(g, kin, RotaryTravel{}, f.sample().q, carry);
      if (fe) {
        const double target = f.sample().feed * period;
        fe->join_max = std::max(fe->join_max, std::abs((before + f.sample().chord) / target - 1.0));
        ++fe->joins;
      }
    }
    while (!f.done()) {
      const RuledSample& x = f.step(g, period);
      ++cycles;
      each(x, seg0, g);
      if (fe && !x.last && x.dfeed == 0.0 && x.target > 0.0) {
        const double e = x.feed_error();
        fe->max = std::max(fe->max, std::abs(e));
        fe->ss += e * e;
        ++fe->n;
      }
    }
    seg0 += g.segment_count;
  }
  return cycles;
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"bench_ruled_follower: the rt's evaluator of a ruled piece: cost, feed error, swept-axis deviation"};
  std::string config = "configs/desktop-5axis.toml";
  double feed_mm_min = 600.0, height = 10.0, tool_length = 0.0, accel = 1000.0;
  app.add_option("--config", config, "machine config (XYZAC)")->show_default();
  app.add_option("--feed", feed_mm_min, "programmed feed, mm/min")->show_default();
  app.add_option("--accel", accel, "the pieces' tangential acceleration, mm/s^2")->show_default();
  app.add_option("--height", height, "the point up the tool axis whose deviation is measured, mm")->show_default();
  app.add_option("--tool-length", tool_length, "tool length, mm")->show_default();
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;
  MachineConfig cfg;
  try {
    cfg = load_config(config);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_ruled_follower: %s\n", e.what());
    return 2;
  }
  Kinematics kin = cfg.kinematics;
  kin.tool_length = tool_length;
  const double F = feed_mm_min / 60.0;
  const double T = cfg.cycle_period_s();
  const BSplineSurface surf = example_surface(25.0, {-12.5, -12.5, -4.5});
  std::vector<PassLine> passes;
  for (const double u : {0.1, 0.5, 0.9}) passes.push_back({surf, u, cfg.gcode.work_offsets[0]});
  std::printf("%s (%s), cycle %.0f Hz; the seed's example scaled to 25 x 25 x 2.5 mm, passes at X = -10, 0, 10 mm "
              "(program) along Y, G54 (%.1f, %.1f, %.1f); F %g mm/min, acceleration %g mm/s^2, tool length %g mm; "
              "blocks of at most %d segments\n",
              cfg.name.c_str(), config.c_str(), cfg.motion.cycle_hz, cfg.gcode.work_offsets[0][0],
              cfg.gcode.work_offsets[0][1], cfg.gcode.work_offsets[0][2], feed_mm_min, accel, tool_length,
              kMaxRuledSegments);

  // Cost per cycle, fastest of 7 runs over all three passes at 1 mm spacing.
  {
    std::vector<Piece> pieces;
    for (const PassLine& p : passes) pieces.push_back(make_piece(p, 1.0, F, accel));
    double best_step = 1e300, best_sample = 1e300;
    long cycles = 0;
    volatile double sink = 0.0;
    for (int trial = 0; trial < 7; ++trial) {
      cycles = 0;
      const auto t0 = Clock::now();
      for (const Piece& pc : pieces) {
        cycles += follow(pc, kin, T, [&](const RuledSample& x, int, const RuledGeometry&) { sink = sink + x.ddq[kRotary]; }, nullptr);
      }
      const auto t1 = Clock::now();
      best_step = std::min(best_step, std::chrono::duration<double>(t1 - t0).count() / cycles);
      // ruled_sample_at alone at the same parameters (every cycle's block, u, feed, dF/dt)
      struct At {
        const RuledGeometry* g;
        double u, feed, dfeed;
        Joints q;
      };
      std::vector<At> at;
      for (const Piece& pc : pieces) {
        follow(
            pc, kin, T,
            [&](const RuledSample& x, int, const RuledGeometry& g) { at.push_back({&g, x.u, x.feed, x.dfeed, x.q}); },
            nullptr);
      }
      const auto t2 = Clock::now();
      for (const At& a : at) {
        const RuledSample s = ruled_sample_at(*a.g, kin, RotaryTravel{}, a.q, a.u, a.feed, a.dfeed);
        sink = sink + s.ddq[kTilt];
      }
      const auto t3 = Clock::now();
      best_sample = std::min(best_sample, std::chrono::duration<double>(t3 - t2).count() / static_cast<double>(at.size()));
    }
    std::printf("\ncost per cycle (fastest of 7 runs, %ld cycles each):\n", cycles);
    std::printf("  RuledFollower::step (speed, Taylor step + chord correction, pose, derivatives, IK, feed-forward)  %8.3f us\n",
                best_step * 1e6);
    std::printf("  ruled_sample_at (pose + derivatives + inverse kinematics + Jacobian rates)                   %8.3f us\n",
                best_sample * 1e6);
    std::printf("  goal < 10 us; the seed paper: 8.14 ms per sample (Pentium MMX 166 MHz)\n");
  }

  // Feed error at constant-feed stretches, and at the block joins.
  std::printf("\nfeed error: chord per cycle against F T at the constant-feed stretches (%%), three passes\n");
  std::printf("  %-8s %-8s %14s %14s %10s %16s %6s\n", "spacing", "period", "max |err| %", "rms err %", "cycles",
              "join max |err| %", "joins");
  for (const double spacing : {0.5, 1.0, 2.0}) {
    for (const double period : {T, 0.01}) {
      FeedError fe;
      for (const PassLine& p : passes) {
        const Piece pc = make_piece(p, spacing, F, accel);
        follow(pc, kin, period, [](const RuledSample&, int, const RuledGeometry&) {}, &fe);
      }
      std::printf("  %-8s %-8s %14.3e %14.3e %10ld %16.3e %6ld\n", (std::to_string(spacing).substr(0, 3) + " mm").c_str(),
                  (std::to_string(period * 1e3).substr(0, 4) + " ms").c_str(), fe.max * 100.0,
                  std::sqrt(fe.ss / std::max(1L, fe.n)) * 100.0, fe.n, fe.join_max * 100.0, fe.joins);
    }
  }

  // Deviation of the swept axis from the intended ruled surface.
  std::printf("\nswept tool axis against the intended ruled surface (the pose the joints command: forward(q)), "
              "the tip and the point %g mm up the axis, um\n",
              height);
  std::printf("  %-8s %-34s %12s %14s %8s\n", "spacing", "method", "tip dev um", "axis@h dev um", "samples");
  for (const double spacing : {0.5, 1.0, 2.0}) {
    Deviation ruled, linear;
    for (const PassLine& pass : passes) {
      const Piece pc = make_piece(pass, spacing, F, accel);
      const int nseg = static_cast<int>(pc.vs.size()) - 1;
      auto bracket = [&](int seg, double& lo, double& hi) {
        seg = std::clamp(seg, 0, nseg - 1);
        lo = pc.vs[std::max(0, seg - 1)];
        hi = pc.vs[std::min(nseg, seg + 2)];
      };
      follow(
          pc, kin, T,
          [&](const RuledSample& x, int seg0, const RuledGeometry&) {
            double lo, hi;
            bracket(seg0 + static_cast<int>(x.u), lo, hi);
            ruled.add(pass, forward(kin, x.q), lo, hi, height);
          },
          nullptr);
      // G1 moves: the tip on the chord at F, A and C linear between the set points' joints
      std::vector<Joints> qs(pc.set.size());
      Joints prev{};
      for (std::size_t i = 0; i < pc.set.size(); ++i) prev = qs[i] = inverse(kin, pc.set[i], prev);
      for (std::size_t i = 0; i + 1 < pc.set.size(); ++i) {
        const double len = norm(pc.set[i + 1].tip - pc.set[i].tip);
        const int steps = std::max(1, static_cast<int>(std::ceil(len / (F * T))));
        for (int k = 0; k < steps; ++k) {
          const double f = static_cast<double>(k) / steps;
          Joints q = qs[i];
          q[kTilt] += f * (qs[i + 1][kTilt] - qs[i][kTilt]);
          q[kRotary] += f * (qs[i + 1][kRotary] - qs[i][kRotary]);
          const ToolPose p{pc.set[i].tip + f * (pc.set[i + 1].tip - pc.set[i].tip), forward(kin, q).axis};
          double lo, hi;
          bracket(static_cast<int>(i), lo, hi);
          linear.add(pass, p, lo, hi, height);
        }
      }
    }
    const std::string sp = std::to_string(spacing).substr(0, 3) + " mm";
    std::printf("  %-8s %-34s %12.4f %14.4f %8ld\n", sp.c_str(), "G1, A and C linear", linear.tip * 1e3, linear.high * 1e3,
                linear.samples);
    std::printf("  %-8s %-34s %12.4f %14.4f %8ld\n", sp.c_str(), "ruled follower (joints, forward)", ruled.tip * 1e3,
                ruled.high * 1e3, ruled.samples);
  }
  std::printf("  goal: within 2 um (issue 17, in the trace; here the commanded joints, no servo)\n");
  return 0;
}
