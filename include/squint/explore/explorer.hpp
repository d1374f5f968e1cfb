// The exploration state machine and motion controller (exploration paper §5.3, plus a
// topological map): scan to find the corridor, follow it centred, stop at its end, look to
// each side and tell an open corridor from a wall by entropy, turn, and prefer unexplored
// branches. Input: camera-derived Percepts and wheel odometry only; output: (v, ω) commands.
#pragma once

#include <string>
#include <vector>

#include "squint/explore/percept.hpp"
#include "squint/explore/topo_map.hpp"

namespace squint::explore {

struct ExplorerOptions {
  // Driving.
  double cruise_speed_mps = 0.6;      // along a corridor (the paper: 0.4)
  double max_omega_rps = 1.2;         // turning in place and steering
  double heading_gain = 2.0;          // ω = gain · (target − heading), rad/s per rad
  double slow_heading_deg = 25.0;     // speed falls linearly to min_speed_fraction at this error
  double min_speed_fraction = 0.25;
  // Heading by vision, propagated by odometry: the corridor axis in the odometry frame is
  // low-pass filtered from each processed frame (axis = odom yaw − fused heading).
  double axis_gain = 0.08;            // per processed frame
  double axis_outlier_deg = 20.0;     // innovations larger than this are ignored
  // Centring from the translation-sensitive cues: lateral cue = centre − fused heading.
  double centre_gain = 1.5;           // target heading = −centre_gain · lateral cue
  double centre_filter = 0.2;         // low-pass of the lateral cue per processed frame
  double max_centre_correction_deg = 12.0;
  // End of the corridor.
  double end_stop_dist_m = 1.1;       // stop when the fused distance to the end is below this
  int end_confirm_frames = 3;         // ... on this many consecutive processed frames
  double min_travel_before_end_m = 0.8;  // after a turn, before an end may be detected
  // Deciding by looking (entropy rule).
  double turn_rate_rps = 1.2;         // rotating in place
  double turn_tolerance_deg = 1.5;
  int settle_frames = 4;              // frames to wait after a rotation before looking
  int look_frames = 4;                // frames whose glance entropy is averaged
  // A side is open when its entropy reaches this fraction of the reference entropy (the median
  // glance entropy while following the corridor just driven, i.e. looking down a corridor).
  double open_entropy_ratio = 0.93;
  int reference_window = 64;          // processed frames kept for the reference median
  // Start-up scan (recovery when starting facing a wall or close to one): a full turn in place,
  // the glance entropy binned by odometry yaw; the robot sets off toward the maximum.
  int scan_bins = 36;
  // Stall guard from odometry alone: commanded forward but the wheels did not move.
  double stall_window_s = 1.0;
  double stall_min_progress_m = 0.05;
  // Obstacle override (used only when Percepts carry ObstacleAdvice).
  double avoid_gain = 1.5;
  double avoid_speed_fraction = 0.5;
  TopoMapOptions map;

  std::string Validate() const;
};

enum class ExploreState {
  kScan,     // start-up full turn, looking for the corridor
  kFollow,   // driving down the corridor
  kProbe,    // stopped at the end: rotating to look left and right
  kTurn,     // rotating to the chosen branch
  kBackOff,  // stalled against something: reversing a little
};
const char* StateName(ExploreState s);

// Something that happened, for logs and maps (positions are odometry poses).
struct ExploreEvent {
  enum class Kind { kScanDone, kEndDetected, kTurn, kStall };
  Kind kind = Kind::kTurn;
  double stamp_s = 0.0;
  Pose2 odom_T_robot;
  int turn_deg = 0;   // for kTurn: +90 left, −90 right, 180 around, 0 straight on
  int node = -1;      // topological node, when known
  std::string note;   // e.g. "left open, right wall"
};

class Explorer {
 public:
  explicit Explorer(const ExplorerOptions& options = {});

  // One camera frame: returns the command to apply until the next frame.
  Command Step(const Percept& percept);

  ExploreState State() const { return state_; }
  // The current heading estimate relative to the corridor axis (degrees), by vision + odometry.
  double HeadingEstimateDeg() const;
  // The distance to the end, propagated by odometry since the last processed frame; negative
  // when unknown.
  double DistEndEstimateM() const { return dist_end_m_; }
  // True once after every new corridor starts: the caller resets the rapid-perception gate's
  // reference entropy (paper §5.3: normalised by the first frame of the corridor).
  bool TakeGateReset();
  // Vision-corrected dead reckoning (odometry translation, yaw drift removed by the corridor
  // axis estimates), in the map frame whose direction 0 is the first corridor's axis.
  const Pose2& MapPose() const { return map_pose_; }
  const TopoMap& Map() const { return map_; }
  const std::vector<ExploreEvent>& Events() const { return events_; }
  int Turns() const { return turns_; }
  int EndsDetected() const { return ends_; }

 private:
  struct Rotation {
    double target_yaw = 0.0;  // odometry frame
    int settle = 0;
  };
  Command FollowStep(const Percept& p);
  Command ScanStep(const Percept& p);
  Command ProbeStep(const Percept& p);
  Command TurnStep(const Percept& p);
  Command BackOffStep(const Percept& p);
  // Rotates toward target; returns true when there and settled.
  bool Rotate(const Percept& p, Rotation& r, Command& cmd) const;
  void UpdateAxis(const Percept& p);
  void UpdateMapPose(const Percept& p);
  void StartFollow(const Percept& p);
  void StartTurnTo(const Percept& p, int dir, int turn_deg, const std::string& note);
  void Decide(const Percept& p);
  double ReferenceEntropy() const;
  void Emit(ExploreEvent::Kind kind, const Percept& p, int turn_deg, const std::string& note);

  ExplorerOptions opt_;
  ExploreState state_ = ExploreState::kScan;
  bool started_ = false;
  TopoMap map_;
  std::vector<ExploreEvent> events_;

  // Odometry and the corridor frame.
  Pose2 last_odom_;
  Pose2 map_pose_;
  double axis_yaw_odom_ = 0.0;  // corridor axis direction in the odometry frame
  double map_yaw_offset_ = 0.0; // map yaw = odom yaw − offset (vision-corrected)
  int dir_ = 0;                 // map direction being driven
  double lateral_cue_deg_ = 0.0;
  bool lateral_valid_ = false;

  // Follow.
  double dist_end_m_ = -1.0;
  int end_count_ = 0;
  double travel_in_corridor_m_ = 0.0;
  std::vector<double> ref_entropy_;  // ring buffer of glance entropies while following
  int ref_next_ = 0;
  double last_ref_entropy_ = 0.0;
  bool gate_reset_ = true;
  // Stall guard.
  double stall_since_s_ = -1.0;
  Pose2 stall_odom_;
  double backoff_until_s_ = 0.0;

  // Scan.
  std::vector<double> scan_sum_;
  std::vector<int> scan_count_;
  double scan_turned_ = 0.0;
  double scan_start_yaw_ = 0.0;
  double scan_prev_yaw_ = 0.0;
  bool scan_rotating_ = true;
  Rotation scan_final_;

  // Probe and turn.
  int node_ = -1;
  int probe_phase_ = 0;  // 0 left, 1 right
  Rotation rot_;
  int look_count_ = 0;
  double look_sum_ = 0.0;
  double side_entropy_[2] = {0.0, 0.0};
  int probe_sides_[2] = {1, 3};  // relative turns (in quarter turns) to probe
  int n_probes_ = 0;
  int turn_to_dir_ = 0;

  int turns_ = 0;
  int ends_ = 0;
};

}  // namespace squint::explore
