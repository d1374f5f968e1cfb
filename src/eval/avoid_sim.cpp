// Closed-loop steering-only runs in the simulator (issue 6).
#include "squint/eval/avoid_sim.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include <fmt/format.h>

#include "squint/eval/plot.hpp"
#include "squint/obstacles/avoid_overlay.hpp"
#include "squint/obstacles/avoider.hpp"
#include "squint/obstacles/ipt_pipeline.hpp"
#include "squint/sim/renderer.hpp"
#include "squint/sim/robot.hpp"

namespace squint::eval {

std::string AvoidSimOptions::Validate() const {
  if (!(duration_s > 0 && duration_s <= 3600)) return "duration_s must be in (0, 3600]";
  if (!(speed_mps > 0 && speed_mps <= 2)) return "speed_mps must be in (0, 2]";
  if (!(period_s >= 0.05 && period_s <= 5)) return "period_s must be in [0.05, 5]";
  if (!(turn_time_s > 0)) return "turn_time_s must be positive";
  if (!(stop_turn_deg > 0 && stop_turn_deg <= 180)) return "stop_turn_deg must be in (0, 180]";
  if (!(start_jitter_m >= 0) || !(start_yaw_jitter_deg >= 0)) return "start jitters must be >= 0";
  if (!(noise_sigma >= 0)) return "noise_sigma must be >= 0";
  if (!(blind_path_m >= 0)) return "blind_path_m must be >= 0";
  return {};
}

BlindMove ChooseBlindMove(obstacles::PairStatus status, bool forward_all_pair, bool path_clear, bool* stalled) {
  const bool no_motion = status == obstacles::PairStatus::kNoMotion;
  const bool stall = no_motion && forward_all_pair;
  if (stalled) *stalled = stall;
  if (stall) return BlindMove::kTurn;
  if ((no_motion || status == obstacles::PairStatus::kPureRotation) && path_clear) return BlindMove::kDriveOn;
  return BlindMove::kTurn;
}

AvoidSimRun RunAvoidSim(const sim::World& world, const config::AvoidFileOptions& options,
                        const AvoidSimOptions& so, std::uint64_t seed) {
  if (const std::string p = so.Validate(); !p.empty()) throw Error("avoid simulation: " + p);
  AvoidSimRun run;
  run.seed = seed;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Pose2 start = world.start;
  const double c = std::cos(start.yaw), s = std::sin(start.yaw);
  const double dy = so.start_jitter_m * unit(rng);
  start.x -= s * dy;
  start.y += c * dy;
  start.yaw = WrapPi(start.yaw + DegToRad(so.start_yaw_jitter_deg) * unit(rng));

  sim::RobotOptions ro;
  ro.odometry.seed = seed * 7919 + 1;
  sim::Robot robot(world, start, ro);
  const CameraModel camera = world.camera.Model();
  sim::RenderOptions rend;
  rend.noise_sigma = so.noise_sigma;
  rend.seed = seed;
  sim::Renderer renderer(world, camera, rend);
  config::AvoidFileOptions opt = options;
  opt.avoid.gap.robot_radius_m = world.robot.radius_m;
  obstacles::IptPipeline ipt(camera, opt.ipt);
  obstacles::Avoider avoider(camera, opt.avoid);
  obstacles::PairResult pair;

  const int steps_per_pair = std::max(1, static_cast<int>(std::lround(so.period_s / ro.step_s)));
  const double max_turn = DegToRad(world.robot.max_turn_rate_dps);
  std::uint64_t frame_id = 0;
  cv::Mat previous = renderer.Render(robot.TruePose(), nullptr, nullptr, frame_id++);
  Pose2 previous_odom = robot.OdomPose();
  double v = so.speed_mps, omega = 0.0;
  double turn_left_rad = 0.0;  // remaining in-place turn after a stop
  bool forward_all_pair = true;  // every step since the last frame was commanded forward
  auto clearance = [&] {
    const Eigen::Vector2d p = robot.TruePose().Translation();
    return std::min(world.DistanceToWalls(p), world.DistanceToObstacles(p)) - world.robot.radius_m;
  };
  run.min_clearance_m = clearance();
  const int total_steps = static_cast<int>(std::lround(so.duration_s / ro.step_s));
  for (int k = 1; k <= total_steps; ++k) {
    if (turn_left_rad > 0) {
      v = 0.0;
      omega = max_turn;
      turn_left_rad -= max_turn * ro.step_s;
      if (turn_left_rad <= 0) {
        omega = 0.0;
        v = so.speed_mps;
      }
    }
    if (!(v > 0.0)) forward_all_pair = false;
    const sim::StepResult step = robot.Step(v, omega);
    if (step.collided) {
      if (run.collisions == 0) {
        run.first_collision_s = robot.Time();
        run.first_hit = step.hit;
      }
      ++run.collisions;
    }
    run.min_clearance_m = std::min(run.min_clearance_m, clearance());
    if (k % steps_per_pair != 0) continue;
    cv::Mat current = renderer.Render(robot.TruePose(), nullptr, nullptr, frame_id++);
    const Pose2 odom = robot.OdomPose();
    if (turn_left_rad <= 0) {
      ipt.Process(previous, current, previous_odom, odom, &pair);
      if (pair.Ok()) {
        ++run.decisions;
        const obstacles::AvoidResult& r = avoider.Process(current, pair.features, odom);
        if (!so.overlay_dir.empty())
          WritePng(so.overlay_dir / fmt::format("{:03d}-{:06d}.png", seed, frame_id),
                   obstacles::DrawAvoidOverlay(current, pair.features, r));
        if (r.decision.stop) {
          ++run.stops;
          turn_left_rad = DegToRad(so.stop_turn_deg);
        } else {
          v = so.speed_mps;
          omega = std::clamp(DegToRad(*r.decision.steer_deg) / so.turn_time_s, -max_turn, max_turn);
        }
      } else {
        // No classification (e.g. too few features facing a plain wall): do not drive on blind;
        // turn as on a stop. Pairs without motion cannot be classified either way: after an
        // in-place turn the robot drives on straight, but only when its footprint is clear of
        // the contacts it remembers. A pair without motion although every step was commanded
        // forward is a stall (the wheels made no progress: something holds the robot): a stop.
        ++run.skipped_pairs;
        ++run.skipped_by_status[obstacles::PairStatusName(pair.status)];
        const bool after_turn =
            pair.status == obstacles::PairStatus::kNoMotion || pair.status == obstacles::PairStatus::kPureRotation;
        bool stalled = false;
        const BlindMove move = ChooseBlindMove(pair.status, forward_all_pair,
                                               after_turn && avoider.StraightPathClear(odom, so.blind_path_m), &stalled);
        if (stalled) ++run.stalls;
        if (move == BlindMove::kDriveOn) {
          v = so.speed_mps;
          omega = 0.0;
        } else {
          if (after_turn && !stalled) ++run.blind_blocked;
          turn_left_rad = DegToRad(so.stop_turn_deg);
        }
      }
    }
    previous = current;
    previous_odom = odom;
    forward_all_pair = true;
  }
  run.time_s = robot.Time();
  run.distance_m = robot.DistanceTravelled();
  return run;
}

}  // namespace squint::eval
