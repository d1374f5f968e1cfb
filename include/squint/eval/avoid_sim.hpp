// Closed-loop check of steering alone in the simulator (issue 6): the robot drives at a fixed
// speed, steers toward the avoidance stage's direction after every frame pair, turns in place
// when it is told to stop, and the simulator counts collisions.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "squint/config/avoid_yaml.hpp"
#include "squint/obstacles/ipt_pipeline.hpp"
#include "squint/sim/world.hpp"

namespace squint::eval {

struct AvoidSimOptions {
  double duration_s = 120.0;     // simulated time per run
  double speed_mps = 0.15;       // forward speed while not stopping
  double period_s = 0.5;         // time between the two frames of a pair (one decision per pair)
  double turn_time_s = 1.0;      // omega = steer / turn_time_s (clipped to the robot's limit)
  double stop_turn_deg = 45.0;   // on a stop: turn this far in place (left), then drive on
  double start_jitter_m = 0.4;   // start pose: uniform lateral offset within ± this
  double start_yaw_jitter_deg = 20.0;
  double noise_sigma = 2.0;      // sensor noise, grey levels
  // Driving on without a classified pair (after an in-place turn) needs this much straight path
  // clear of the remembered contacts (robot radius + margin to each side).
  double blind_path_m = 0.3;
  std::filesystem::path overlay_dir;  // when set, one overlay PNG per decision goes here
  std::string Validate() const;
};

struct AvoidSimRun {
  std::uint64_t seed = 0;
  double time_s = 0.0;
  double distance_m = 0.0;
  int collisions = 0;           // simulation steps that would have hit something
  double first_collision_s = -1.0;
  std::string first_hit;        // what it hit first
  int decisions = 0, stops = 0, skipped_pairs = 0;
  int stalls = 0;         // pairs without motion although driven forward: treated as stops
  int blind_blocked = 0;  // unclassified pairs after a turn whose straight path was not clear
  std::map<std::string, int> skipped_by_status;  // IPT status name -> pairs
  double min_clearance_m = 0.0;  // smallest distance from the robot's disc to a wall or obstacle
};

// What the robot does after a frame pair the IPT stage could not classify.
enum class BlindMove {
  kDriveOn,  // drive on straight (the pair followed an in-place turn and the path is clear)
  kTurn,     // turn in place, as on a stop
};
// `forward_all_pair`: every step since the earlier frame was commanded forward; `path_clear`:
// the footprint's straight path is clear of the remembered contacts. A pair without motion
// although driven forward is a stall (the wheels made no progress): `*stalled` is set and the
// robot turns. Pairs without motion or with pure rotation (after an in-place turn) drive on
// only along a clear path; any other failure (too few features, e.g. facing a plain wall)
// turns.
BlindMove ChooseBlindMove(obstacles::PairStatus status, bool forward_all_pair, bool path_clear, bool* stalled);

// One seeded run (the seed sets the start pose, the sensor noise and the odometry noise). The
// avoidance options' robot radius is taken from the world. Throws squint::Error for bad options.
AvoidSimRun RunAvoidSim(const sim::World& world, const config::AvoidFileOptions& options,
                        const AvoidSimOptions& sim_options, std::uint64_t seed);

}  // namespace squint::eval
