// The exploration state machine: scan, follow (heading by vision propagated by odometry,
// centring by translation-sensitive cues), stop at the end, probe both sides by entropy, turn.
#include "squint/explore/explorer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::explore {
namespace {

// Whether a cue with this axis gain (0: off) moved the axis at since_s (negative: never) no more
// than hold_s before stamp_s: the glance's inliers then leave the axis to it.
bool SteeredWithin(double gain, double since_s, double stamp_s, double hold_s) {
  return gain > 0.0 && since_s >= 0.0 && stamp_s - since_s <= hold_s;
}

// printf-style formatting into a std::string (events only, never per frame in steady state).
std::string Format(const char* fmt, ...) {
  char buf[256];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  return buf;
}

bool Positive(double x) { return std::isfinite(x) && x > 0.0; }
bool NonNegative(double x) { return std::isfinite(x) && x >= 0.0; }

// Entropy samples of the corridor being followed before they make its reference (until then the
// reference is carried over from the corridor before or the start-up scan).
constexpr int kOwnReferenceSamples = 8;
// Backing off, in reverse (m/s).
constexpr double kReverseMps = 0.2;
// The walls' lines' views of the corridor ahead count this long (their frame comes every third
// frame while following or probing: about five views, at least half of which must show it free;
// a tiled floor's joints make single views scatter), taken facing within this of the direction.
constexpr double kWallLineAheadHoldS = 0.5;
constexpr double kWallLineAheadYawDeg = 20.0;

}  // namespace

std::string ExplorerOptions::Validate() const {
  if (!Positive(cruise_speed_mps)) return "cruise_speed_mps must be positive";
  if (!Positive(max_omega_rps)) return "max_omega_rps must be positive";
  if (!Positive(heading_gain)) return "heading_gain must be positive";
  if (!Positive(slow_heading_deg)) return "slow_heading_deg must be positive";
  if (!(min_speed_fraction > 0.0 && min_speed_fraction <= 1.0)) return "min_speed_fraction must be in (0, 1]";
  if (!(axis_gain > 0.0 && axis_gain <= 1.0)) return "axis_gain must be in (0, 1]";
  if (!Positive(axis_outlier_deg)) return "axis_outlier_deg must be positive";
  if (!NonNegative(centre_gain)) return "centre_gain must be >= 0";
  if (!(centre_filter > 0.0 && centre_filter <= 1.0)) return "centre_filter must be in (0, 1]";
  if (!NonNegative(max_centre_correction_deg)) return "max_centre_correction_deg must be >= 0";
  if (!Positive(end_stop_dist_m)) return "end_stop_dist_m must be positive";
  if (end_confirm_frames < 1) return "end_confirm_frames must be >= 1";
  if (end_median_frames < 1) return "end_median_frames must be >= 1";
  if (!(end_entropy_ratio >= 0.0 && end_entropy_ratio < 1.0)) return "end_entropy_ratio must be in [0, 1)";
  if (!(reference_percentile >= 0.0 && reference_percentile <= 1.0)) return "reference_percentile must be in [0, 1]";
  if (axis_reacquire_frames < 1) return "axis_reacquire_frames must be >= 1";
  if (!(filtered_axis_gain >= 0.0 && filtered_axis_gain <= 1.0)) return "filtered_axis_gain must be in [0, 1]";
  if (!NonNegative(heading_filter_prior_std_deg)) return "heading_filter_prior_std_deg must be >= 0";
  if (reprobe_dead_end_visits < 0) return "reprobe_dead_end_visits must be >= 0";
  if (align_frames < 1) return "align_frames must be >= 1";
  if (!Positive(align_done_deg)) return "align_done_deg must be positive";
  if (align_rounds < 0) return "align_rounds must be >= 0";
  if (!NonNegative(min_travel_before_end_m)) return "min_travel_before_end_m must be >= 0";
  if (!Positive(turn_rate_rps)) return "turn_rate_rps must be positive";
  if (!Positive(turn_tolerance_deg)) return "turn_tolerance_deg must be positive";
  if (settle_frames < 0) return "settle_frames must be >= 0";
  if (look_frames < 1) return "look_frames must be >= 1";
  if (!(open_entropy_ratio > 0.0 && open_entropy_ratio <= 2.0)) return "open_entropy_ratio must be in (0, 2]";
  if (reference_window < 1) return "reference_window must be >= 1";
  if (scan_bins < 8) return "scan_bins must be >= 8";
  if (!Positive(scan_rate_rps)) return "scan_rate_rps must be positive";
  if (!Positive(stall_window_s)) return "stall_window_s must be positive";
  if (!NonNegative(stall_min_progress_m)) return "stall_min_progress_m must be >= 0";
  if (!Positive(contact_min_v_mps)) return "contact_min_v_mps must be positive";
  if (contact_frames < 1 || contact_frames > 100) return "contact_frames must be in [1, 100]";
  if (!(contact_max_progress > 0.0 && contact_max_progress < 1.0)) return "contact_max_progress must be in (0, 1)";
  if (!NonNegative(contact_point_gap_m)) return "contact_point_gap_m must be >= 0";
  if (!NonNegative(contact_reverse_m) || contact_reverse_m > 1.0) return "contact_reverse_m must be in [0, 1]";
  if (!NonNegative(arrival_min_travel_m)) return "arrival_min_travel_m must be >= 0";
  if (!NonNegative(shift_stall_s)) return "shift_stall_s must be >= 0";
  if (!NonNegative(shift_points_within_m) || shift_points_within_m > 5.0) return "shift_points_within_m must be in [0, 5]";
  if (!(blind_texture_ratio >= 0.0 && blind_texture_ratio < 1.0)) return "blind_texture_ratio must be in [0, 1)";
  if (!(wall_view_hold_m >= 0.0 && wall_view_hold_m <= 10.0)) return "wall_view_hold_m must be in [0, 10]";
  if (!(wall_view_hold_deg > 0.0 && wall_view_hold_deg <= 180.0)) return "wall_view_hold_deg must be in (0, 180]";
  if (!(wall_view_hold_s > 0.0 && wall_view_hold_s <= 60.0)) return "wall_view_hold_s must be in (0, 60]";
  if (!(wall_lines_hold_s >= 0.0 && wall_lines_hold_s <= 60.0)) return "wall_lines_hold_s must be in [0, 60]";
  if (!(scan_wall_lines >= 0.0 && scan_wall_lines <= 1.0)) return "scan_wall_lines must be in [0, 1]";
  if (!(blind_texture_start_m >= 0.0 && blind_texture_start_m <= 1000.0)) return "blind_texture_start_m must be in [0, 1000]";
  if (!Positive(blind_texture_min_floor)) return "blind_texture_min_floor must be positive";
  if (!NonNegative(blind_texture_hold_s)) return "blind_texture_hold_s must be >= 0";
  if (blind_texture_min_floor_columns < 1) return "blind_texture_min_floor_columns must be >= 1";
  if (!NonNegative(sonar_end_blocks_m)) return "sonar_end_blocks_m must be >= 0";
  if (!(known_end_slow_m >= 0.0 && known_end_slow_m <= 20.0)) return "known_end_slow_m must be in [0, 20]";
  if (!(known_end_disagree_m >= 0.0 && known_end_disagree_m <= 20.0)) return "known_end_disagree_m must be in [0, 20]";
  if (!NonNegative(avoid_gain)) return "avoid_gain must be >= 0";
  if (!(avoid_speed_fraction > 0.0 && avoid_speed_fraction <= 1.0)) return "avoid_speed_fraction must be in (0, 1]";
  if (!Positive(avoid_hold_s)) return "avoid_hold_s must be positive";
  if (avoid_blocked_frames < 1) return "avoid_blocked_frames must be >= 1";
  if (avoid_confirm_advices < 1) return "avoid_confirm_advices must be >= 1";
  if (!Positive(robot_radius_m)) return "robot_radius_m must be positive";
  if (!NonNegative(safety_margin_m)) return "safety_margin_m must be >= 0";
  if (!NonNegative(stop_margin_m)) return "stop_margin_m must be >= 0";
  if (!Positive(speed_per_free_mps)) return "speed_per_free_mps must be positive";
  if (!Positive(lookahead_m)) return "lookahead_m must be positive";
  if (!Positive(gap_step_deg)) return "gap_step_deg must be positive";
  if (gap_steps < 0 || gap_steps > 36) return "gap_steps must be in [0, 36]";
  if (!NonNegative(gap_cost_per_deg)) return "gap_cost_per_deg must be >= 0";
  if (!NonNegative(gap_side_wall_max_m)) return "gap_side_wall_max_m must be >= 0";
  if (!Positive(sonar_end_free_m)) return "sonar_end_free_m must be positive";
  if (!Positive(sonar_end_gap_m)) return "sonar_end_gap_m must be positive";
  if (!Positive(sonar_open_free_m)) return "sonar_open_free_m must be positive";
  if (!(sonar_open_min_entropy_ratio >= 0.0 && sonar_open_min_entropy_ratio <= 2.0)) return "sonar_open_min_entropy_ratio must be in [0, 2]";
  if (!NonNegative(sonar_centre_gain)) return "sonar_centre_gain must be >= 0";
  if (!Positive(sonar_centre_max_lateral_m)) return "sonar_centre_max_lateral_m must be positive";
  if (!NonNegative(light_centre_gain)) return "light_centre_gain must be >= 0";
  if (!Positive(light_heading_gate_deg)) return "light_heading_gate_deg must be positive";
  if (!Positive(light_max_lateral_m)) return "light_max_lateral_m must be positive";
  if (light_confirm < 1) return "light_confirm must be at least 1";
  if (!Positive(light_agree_m)) return "light_agree_m must be positive";
  if (!NonNegative(light_hold_s)) return "light_hold_s must be >= 0";
  if (!Positive(rescan_yaw_deg)) return "rescan_yaw_deg must be positive";
  if (!NonNegative(trust_memory_after_m)) return "trust_memory_after_m must be >= 0";
  if (!NonNegative(settled_blocked_min_range_m)) return "settled_blocked_min_range_m must be >= 0";
  if (!NonNegative(setoff_blocked_min_range_m)) return "setoff_blocked_min_range_m must be >= 0";
  if (!(setoff_standing_hold_m >= 0.0 && setoff_standing_hold_m <= 1.0)) return "setoff_standing_hold_m must be in [0, 1]";
  if (!(mirror_wall_half_span_m > 0.0 && mirror_wall_half_span_m <= 10.0)) return "mirror_wall_half_span_m must be in (0, 10]";
  if (const std::string e = mirror.Validate(); !e.empty()) return e;
  if (const std::string e = near_edges.Validate(); !e.empty()) return "near_edges." + e;
  if (!(probe_max_wall_lines >= 0.0 && probe_max_wall_lines <= 1.0)) return "probe_max_wall_lines must be in [0, 1]";
  if (!(trust_memory_max_wall_lines >= 0.0 && trust_memory_max_wall_lines <= 1.0)) return "trust_memory_max_wall_lines must be in [0, 1]";
  if (!(blind_view_fraction > 0.0 && blind_view_fraction <= 1.0)) return "blind_view_fraction must be in (0, 1]";
  if (!NonNegative(blind_view_entropy_ratio)) return "blind_view_entropy_ratio must be >= 0";
  if (!(blind_view_max_wall_lines >= 0.0 && blind_view_max_wall_lines <= 1.0)) return "blind_view_max_wall_lines must be in [0, 1]";
  if (wall_axis_min_pairs < 1) return "wall_axis_min_pairs must be >= 1";
  if (!(wall_axis_min_strength >= 0.0 && wall_axis_min_strength <= 1.0)) return "wall_axis_min_strength must be in [0, 1]";
  if (!(wall_axis_gain > 0.0 && wall_axis_gain <= 1.0)) return "wall_axis_gain must be in (0, 1]";
  if (!Positive(side_window_m)) return "side_window_m must be positive";
  if (!Positive(side_wall_max_lateral_m)) return "side_wall_max_lateral_m must be positive";
  if (!NonNegative(branch_wall_before_m)) return "branch_wall_before_m must be >= 0";
  if (!NonNegative(branch_wall_gap_m)) return "branch_wall_gap_m must be >= 0";
  if (!Positive(branch_min_width_m)) return "branch_min_width_m must be positive";
  if (!(branch_default_width_m >= branch_min_width_m && std::isfinite(branch_default_width_m)))
    return "branch_default_width_m must be >= branch_min_width_m";
  if (!(branch_max_width_m >= branch_default_width_m && std::isfinite(branch_max_width_m)))
    return "branch_max_width_m must be >= branch_default_width_m";
  if (!Positive(branch_depth_m)) return "branch_depth_m must be positive";
  if (!Positive(branch_max_heading_deg)) return "branch_max_heading_deg must be positive";
  if (!Positive(branch_known_radius_m)) return "branch_known_radius_m must be positive";
  if (!NonNegative(branch_line_tolerance_m)) return "branch_line_tolerance_m must be >= 0";
  if (!NonNegative(branch_coarse_from_m)) return "branch_coarse_from_m must be >= 0";
  if (!(branch_line_band_m >= branch_line_tolerance_m && std::isfinite(branch_line_band_m)))
    return "branch_line_band_m must be >= branch_line_tolerance_m";
  if (branch_line_samples < 1) return "branch_line_samples must be at least 1";
  if (!NonNegative(branch_line_spacing_m) || branch_line_spacing_m > 1.0) return "branch_line_spacing_m must be in [0, 1]";
  if (!NonNegative(wall_line_align_over_deg) || wall_line_align_over_deg > 45.0)
    return "wall_line_align_over_deg must be in [0, 45]";
  if (!NonNegative(scan_entropy_floor) || scan_entropy_floor > 1.0) return "scan_entropy_floor must be in [0, 1]";
  if (!NonNegative(scan_wall_entropy) || scan_wall_entropy > 1.0) return "scan_wall_entropy must be in [0, 1]";
  if (!NonNegative(light_axis_gain) || light_axis_gain > 1.0) return "light_axis_gain must be in [0, 1]";
  if (!NonNegative(light_drift_gain) || light_drift_gain > 1.0) return "light_drift_gain must be in [0, 1]";
  if (!Positive(light_drift_gate_deg) || !Positive(light_drift_window_m) || !Positive(light_drift_max_rms_m) ||
      !Positive(light_drift_max_deg) || !NonNegative(light_drift_min_span_m) || light_drift_min_readings < 3)
    return "light_drift_*: gate, window, residual and angle must be positive, min readings >= 3";
  if (!Positive(light_axis_gate_deg)) return "light_axis_gate_deg must be positive";
  if (!NonNegative(wall_line_axis_gain) || wall_line_axis_gain > 1.0) return "wall_line_axis_gain must be in [0, 1]";
  if (!Positive(wall_line_gate_deg) || wall_line_gate_deg > 45.0) return "wall_line_gate_deg must be in (0, 45]";
  if (wall_line_confirm < 1) return "wall_line_confirm must be at least 1";
  if (!NonNegative(wall_line_agree_deg)) return "wall_line_agree_deg must be >= 0";
  if (!Positive(wall_line_hold_s)) return "wall_line_hold_s must be positive";
  if (!NonNegative(wall_line_min_diff_deg)) return "wall_line_min_diff_deg must be >= 0";
  if (!NonNegative(wall_line_free_m)) return "wall_line_free_m must be >= 0";
  if (!NonNegative(wall_keep_m) || wall_keep_m > 2.0) return "wall_keep_m must be in [0, 2]";
  if (!NonNegative(wall_keep_min_m) || wall_keep_min_m > 2.0) return "wall_keep_min_m must be in [0, 2]";
  if (!NonNegative(wall_keep_gain_deg_per_m)) return "wall_keep_gain_deg_per_m must be >= 0";
  if (!NonNegative(wall_keep_max_deg) || wall_keep_max_deg > 45.0) return "wall_keep_max_deg must be in [0, 45]";
  if (!NonNegative(wall_keep_gate_deg) || wall_keep_gate_deg > 45.0) return "wall_keep_gate_deg must be in [0, 45]";
  if (!NonNegative(mouth_centre_min_m)) return "mouth_centre_min_m must be >= 0";
  if (!(mouth_centre_max_m >= mouth_centre_min_m && std::isfinite(mouth_centre_max_m)))
    return "mouth_centre_max_m must be >= mouth_centre_min_m";
  if (!NonNegative(mouth_back_max_m)) return "mouth_back_max_m must be >= 0";
  if (!(mouth_band_m > 0.25 && std::isfinite(mouth_band_m))) return "mouth_band_m must be above 0.25";
  if (!Positive(mouth_speed_mps)) return "mouth_speed_mps must be positive";
  if (std::string e = memory.Validate(); !e.empty()) return "memory." + e;
  if (std::string e = map.Validate(); !e.empty()) return "map." + e;
  if (!NonNegative(guard_unknown_step_m)) return "guard_unknown_step_m must be >= 0";
  if (!NonNegative(guard_unknown_inner_m)) return "guard_unknown_inner_m must be >= 0";
  if (!NonNegative(guard_unknown_after_m)) return "guard_unknown_after_m must be >= 0";
  return {};
}

const char* StateName(ExploreState s) {
  switch (s) {
    case ExploreState::kScan: return "scan";
    case ExploreState::kFollow: return "follow";
    case ExploreState::kProbe: return "probe";
    case ExploreState::kTurn: return "turn";
    case ExploreState::kBackOff: return "backoff";
    case ExploreState::kAlign: return "align";
  }
  return "?";
}

namespace {
ObstacleMemoryOptions MemoryOptions(const ExplorerOptions& o) {
  ObstacleMemoryOptions m = o.memory;
  m.mark_known_free = m.mark_known_free || o.guard_unknown_step_m > 0.0;
  return m;
}
MirrorWatchOptions MirrorOptions(const ExplorerOptions& o) {
  MirrorWatchOptions m = o.mirror;
  m.body_radius_m = o.robot_radius_m;  // the reflection is the robot's own disc
  return m;
}
}  // namespace

Explorer::Explorer(const ExplorerOptions& options)
    : opt_(options), map_(options.map), memory_(MemoryOptions(options)), mirror_(MirrorOptions(options)),
      near_edge_ranger_(options.near_edges) {
  const std::string err = opt_.Validate();
  SQUINT_ENSURE(err.empty(), "ExplorerOptions: " + err);
  ref_entropy_.reserve(static_cast<std::size_t>(opt_.reference_window));
  scan_sum_.assign(static_cast<std::size_t>(opt_.scan_bins), 0.0);
  scan_count_.assign(static_cast<std::size_t>(opt_.scan_bins), 0);
  scan_views_.assign(static_cast<std::size_t>(opt_.scan_bins), 0);
  scan_wall_views_.assign(static_cast<std::size_t>(opt_.scan_bins), 0);
}

double Explorer::HeadingEstimateDeg() const { return RadToDeg(WrapPi(last_odom_.yaw - axis_yaw_odom_)); }

bool Explorer::TakeGateReset() {
  const bool r = gate_reset_;
  gate_reset_ = false;
  return r;
}

bool Explorer::TakeHeadingFilterReset(double* prior_deg) {
  const bool r = heading_filter_reset_;
  heading_filter_reset_ = false;
  if (prior_deg != nullptr) {
    *prior_deg = std::numeric_limits<double>::quiet_NaN();
    if (r && heading_filter_prior_ && opt_.heading_filter_prior_std_deg > 0.0 && started_)
      *prior_deg = RadToDeg(WrapPi(last_odom_.yaw - axis_yaw_odom_));
  }
  return r;
}

void Explorer::Emit(ExploreEvent::Kind kind, const Percept& p, int turn_deg, const std::string& note) {
  events_.push_back(ExploreEvent{kind, p.stamp_s, p.odom_T_robot, turn_deg, node_, note});
}

Command Explorer::Step(const Percept& p) {
  if (!started_) {
    started_ = true;
    last_odom_ = p.odom_T_robot;
    scan_start_yaw_ = p.odom_T_robot.yaw;
    scan_prev_yaw_ = p.odom_T_robot.yaw;
    map_yaw_offset_ = p.odom_T_robot.yaw;
    axis_yaw_odom_ = p.odom_T_robot.yaw;
    state_ = ExploreState::kAlign;  // look first; scan only when the view is not a corridor
  }
  const Pose2 moved = Between(last_odom_, p.odom_T_robot);
  UpdateMapPose(p, moved);
  memory_.MarkFootprint(p.odom_T_robot, opt_.robot_radius_m, p.stamp_s);  // with guard_unknown_step_m
  UpdateSonar(p);
  NoteWallLinesAhead(p);
  Command cmd;
  if (FeelContact(p, moved)) {
    last_cmd_ = cmd;
    last_cmd_s_ = p.stamp_s;
    return cmd;
  }
  switch (state_) {
    case ExploreState::kScan: cmd = ScanStep(p); break;
    case ExploreState::kFollow: cmd = FollowStep(p); break;
    case ExploreState::kProbe: cmd = ProbeStep(p); break;
    case ExploreState::kTurn: cmd = TurnStep(p); break;
    case ExploreState::kBackOff: cmd = BackOffStep(p); break;
    case ExploreState::kAlign: cmd = AlignStep(p); break;
  }
  last_cmd_ = Guard(p, cmd);
  last_cmd_s_ = p.stamp_s;
  return last_cmd_;
}

// --- Visual sonar -------------------------------------------------------------------------------

void Explorer::UpdateSonar(const Percept& p) {
  view_is_wall_ = false;
  if (p.sonar == nullptr) return;
  const std::vector<SonarColumn>* scan = p.sonar;
  // The walls' lines' frame's bottom texture (blind_texture_ratio): whether sonar column i of n
  // has a bottom as smooth as a wall's.
  const std::vector<float>* tex = BlindTexture(p);
  auto smooth = [&](std::size_t i, std::size_t n) {
    const std::size_t w = tex->size();  // the lines' frame's columns over sonar column i (the same camera, scaled)
    const std::size_t u0 = i * w / n, u1 = std::max(u0 + 1, (i + 1) * w / n);
    double sum = 0.0;
    for (std::size_t u = u0; u < u1; ++u) sum += (*tex)[u];
    return sum / static_cast<double>(u1 - u0) < opt_.blind_texture_ratio * floor_texture_ref_;
  };
  bool blind_view = false;
  if (opt_.blind_view_entropy_ratio > 0.0 && !p.sonar->empty() && p.glance_entropy_nats) {
    int blocked = 0;
    for (const SonarColumn& c : *p.sonar) blocked += c.kind == SonarReturn::kBlockedNear ? 1 : 0;
    // Before any corridor was seen (start-up), the start's absolute "corridor view" entropy.
    const double ref = ReferenceEntropy();
    const double threshold = ref > 0.0 ? opt_.blind_view_entropy_ratio * ref : opt_.start_corridor_entropy_nats;
    const bool view = blocked >= opt_.blind_view_fraction * static_cast<double>(p.sonar->size());
    // While following, a view with a brick wall's periodic mortar lines is a wall whatever its
    // entropy (the lines keep it at corridor level); turning in place keeps the entropy rule (the
    // probe's view of a branch mouth beside a brick corner).
    const bool wall_lines = opt_.blind_view_max_wall_lines > 0.0 && state_ == ExploreState::kFollow &&
                            p.sonar_wall_lines >= opt_.blind_view_max_wall_lines;
    view_is_wall_ = view && (*p.glance_entropy_nats < threshold || wall_lines);
    if (view_is_wall_) {
      wall_view_odometer_m_ = odometer_m_;
      wall_view_yaw_ = p.odom_T_robot.yaw;
      wall_view_s_ = p.stamp_s;
    } else if (view && opt_.wall_view_hold_m > 0.0 && wall_view_odometer_m_ >= 0.0 &&
               odometer_m_ - wall_view_odometer_m_ <= opt_.wall_view_hold_m &&
               p.stamp_s - wall_view_s_ <= opt_.wall_view_hold_s &&
               std::abs(WrapPi(p.odom_T_robot.yaw - wall_view_yaw_)) <= DegToRad(opt_.wall_view_hold_deg)) {
      view_is_wall_ = true;  // held: the entropy hovering at the threshold facing a box up close
    }
    if (view && !view_is_wall_) {
      // A corridor view in the glance, no floor contrast in the sonar: no information, except
      // where the walls' lines' frame shows a column's bottom smooth (blind_texture_ratio).
      sonar_copy_ = *p.sonar;
      const std::size_t n = sonar_copy_.size();
      for (std::size_t i = 0; i < n; ++i) {
        SonarColumn& c = sonar_copy_[i];
        if (c.kind != SonarReturn::kBlockedNear) continue;
        if (tex != nullptr && smooth(i, n)) {
          ++blind_texture_kept_;
          continue;
        }
        c.kind = SonarReturn::kUnknown;
      }
      blind_view = true;
      scan = &sonar_copy_;
      ++blind_views_;
    }
  }
  const bool unknown_rule =
      opt_.blind_texture_unknown ||
      (opt_.blind_texture_start_m > 0.0 && odometer_m_ < opt_.blind_texture_start_m && !stalled_since_start_);
  if (tex != nullptr && !blind_view && unknown_rule) {
    // The sonar's own unknown columns (no step, the bottom rows of the floor's grey) whose bottom
    // is smooth: a wall of the floor's grey within the blind range. Only where every column the
    // sonar shows floor at the bottom of (a boundary or far beyond the blind range) is textured
    // there, at least blind_texture_min_floor_columns of them: on a tiled floor the bottom rows often lie
    // within one smooth tile.
    const std::size_t n = p.sonar->size();
    int floor_columns = 0, smooth_floor = 0, unknown_smooth = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const SonarColumn& c = (*p.sonar)[i];
      const bool floor = c.kind == SonarReturn::kFar ||
                         (c.kind == SonarReturn::kBoundary && c.range_m >= p.sonar_near_blind_m + 0.5);
      if (floor) {
        ++floor_columns;
        smooth_floor += smooth(i, n) ? 1 : 0;
      } else if (c.kind == SonarReturn::kUnknown && smooth(i, n)) {
        ++unknown_smooth;
      }
    }
    if (unknown_smooth > 0 && smooth_floor == 0 && floor_columns >= opt_.blind_texture_min_floor_columns) {
      sonar_copy_ = *p.sonar;
      for (std::size_t i = 0; i < n; ++i) {
        SonarColumn& c = sonar_copy_[i];
        if (c.kind != SonarReturn::kUnknown || !smooth(i, n)) continue;
        c.kind = SonarReturn::kBlockedNear;
        c.range_m = 0.0;
        c.own_range_m = 0.0;
        ++blind_texture_kept_;
      }
      scan = &sonar_copy_;
    }
  }
  last_scan_blind_ = blind_view;
  memory_.Update(*scan, p.odom_T_robot, p.stamp_s, p.sonar_near_blind_m);
  // Setting off, a vertical edge ranged inside the blind range by the robot's own travel.
  if (opt_.setoff_near_edges && setting_off_ && opt_.setoff_blocked_min_range_m > 0.0 && p.sonar_profile != nullptr &&
      p.sonar_profile->size() == p.sonar->size() && p.sonar->size() >= 4) {
    edge_bearings_.resize(p.sonar->size());
    for (std::size_t i = 0; i < p.sonar->size(); ++i) edge_bearings_[i] = (*p.sonar)[i].bearing_rad;
    const int n = static_cast<int>(p.sonar->size());
    // Columns that see no floor step: blocked near, or unknown (a face of the floor's grey).
    auto hidden = [&](int i) {
      const SonarReturn k = (*p.sonar)[static_cast<std::size_t>(std::clamp(i, 0, n - 1))].kind;
      return k == SonarReturn::kBlockedNear || k == SonarReturn::kUnknown;
    };
    for (const NearEdge& e : near_edge_ranger_.Process(*p.sonar_profile, edge_bearings_, p.odom_T_robot)) {
      if (e.range_m > p.sonar_near_blind_m) continue;
      // Something standing inside the blind range hides the floor in its own columns: on one
      // side of the edge at least two of the three nearest columns show no floor step.
      const int c = static_cast<int>(std::lround(e.column));
      int left = 0, right = 0;
      for (int k = 1; k <= 3; ++k) {
        left += hidden(c - k) ? 1 : 0;
        right += hidden(c + k) ? 1 : 0;
      }
      if (std::max(left, right) < 2) continue;
      memory_.InsertConfirmed(e.point, p.stamp_s);
      ++near_edges_ranged_;
    }
  } else {
    near_edge_ranger_.Reset();
  }
  if (opt_.mirror_watch && mirror_.Update(*p.sonar, p.odom_T_robot, p.stamp_s)) {
    const Mirror& m = mirror_.Latest();
    const Eigen::Vector2d along(-m.normal.y(), m.normal.x());
    const double step = 0.5 * opt_.memory.cell_m;
    for (double s = -opt_.mirror_wall_half_span_m; s <= opt_.mirror_wall_half_span_m + 1e-9; s += step)
      memory_.InsertConfirmed(m.point + s * along, p.stamp_s);
  }
  // A blind view with a corridor in the glance: nothing stands within the blind range ahead, so
  // what the memory holds there (a floor-material edge taken for a wall from farther back, e.g.
  // at the mouth of default's carpeted middle corridor) goes.
  if (blind_view && opt_.blind_view_clears) memory_.ClearUnknownRays(sonar_copy_, p.odom_T_robot, p.sonar_near_blind_m);
  ClearFloorEdgeBand(p);
  memory_.Gather(p.odom_T_robot, p.stamp_s);
  sonar_seen_ = true;
  last_scan_yaw_ = p.odom_T_robot.yaw;
  last_wall_lines_ = p.sonar_wall_lines;
  if (opt_.wall_lines_hold_s > 0.0) {
    while (!wall_lines_recent_.empty() && p.stamp_s - wall_lines_recent_.front().first > opt_.wall_lines_hold_s)
      wall_lines_recent_.pop_front();
    wall_lines_recent_.emplace_back(p.stamp_s, p.sonar_wall_lines);
    for (const auto& [stamp, fraction] : wall_lines_recent_) last_wall_lines_ = std::max(last_wall_lines_, fraction);
  }
}

const std::vector<float>* Explorer::BlindTexture(const Percept& p) {
  if (!(opt_.blind_texture_ratio > 0.0) || p.wall_bottom_texture == nullptr || p.wall_bottom_texture->empty()) return nullptr;
  std::vector<float>& v = texture_sorted_;
  v.assign(p.wall_bottom_texture->begin(), p.wall_bottom_texture->end());
  const std::size_t k = (v.size() * 9) / 10;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  // blind_texture_keep_ref: a frame smooth all over by the floor's recent reference (a wall of
  // plain paint filling the view, no floor below it) does not become the reference itself.
  const bool held = p.stamp_s - floor_texture_ref_s_ <= opt_.blind_texture_hold_s;
  // blind_texture_keep_peak: judged against the largest reference of the hold, not the latest.
  std::deque<std::pair<double, double>>& peaks = floor_texture_peaks_;
  while (!peaks.empty() && p.stamp_s - peaks.front().first > opt_.blind_texture_hold_s) peaks.pop_front();
  const double against = opt_.blind_texture_keep_peak && !peaks.empty() ? peaks.front().second : floor_texture_ref_;
  const bool smooth_all_over = opt_.blind_texture_keep_ref && held && against > 0.0 &&
                               v[k] < opt_.blind_texture_ratio * against;
  if (v[k] >= opt_.blind_texture_min_floor && !smooth_all_over) {
    floor_texture_ref_ = v[k];
    floor_texture_ref_s_ = p.stamp_s;
    while (!peaks.empty() && peaks.back().second <= v[k]) peaks.pop_back();
    peaks.emplace_back(p.stamp_s, v[k]);
  }
  if (p.stamp_s - floor_texture_ref_s_ > opt_.blind_texture_hold_s) return nullptr;
  return p.wall_bottom_texture;
}

bool Explorer::WallAxis(double* axis_mod90) const {
  if (!opt_.axis_from_walls || !sonar_seen_) return false;
  double strength = 0.0;
  int pairs = 0;
  *axis_mod90 = memory_.WallAxisMod90(&strength, &pairs);
  return pairs >= opt_.wall_axis_min_pairs && strength >= opt_.wall_axis_min_strength;
}

void Explorer::RotateAxis(double by_rad) {
  axis_yaw_odom_ = WrapPi(axis_yaw_odom_ + by_rad);
  map_yaw_offset_ = WrapPi(map_yaw_offset_ + by_rad);
}

void Explorer::ClearFloorEdgeBand(const Percept& p) {
  if (!floor_edge_band_) return;
  const FloorEdgeBand& b = *floor_edge_band_;
  if (state_ != ExploreState::kFollow || travel_in_corridor_m_ > b.s1 + opt_.robot_radius_m) {
    floor_edge_band_.reset();
    return;
  }
  memory_.ClearRect(b.frame, b.s0, b.s1, b.l0, b.l1);
  memory_.Gather(p.odom_T_robot, p.stamp_s);
}

double Explorer::WallRunEndAlong(int side) const {
  return sides_[side].wall_last_m - opt_.side_window_m - travel_in_corridor_m_;
}

bool Explorer::ShiftingAfterTravel() const {
  return state_ == ExploreState::kTurn && shift_m_ > 0.0 && travel_in_corridor_m_ >= opt_.trust_memory_after_m;
}

bool Explorer::UseBlocked(double yaw) const {
  // After driving down the corridor for more than the blind range, what lies in the blind zone
  // ahead was seen from farther back (and is remembered): the latest scan's blocked-near columns
  // then block only the narrow sector (on textured floors they are mostly floor without a visible
  // step).
  // Likewise while crossing the floor edge of an opening just turned into (floor_edge_band_).
  // And on the drive forward to a mouth's centre, when the robot came along (shift_trusts_memory).
  const bool shifting = opt_.shift_trusts_memory && ShiftingAfterTravel();
  return !((shifting || (state_ == ExploreState::kFollow &&
                         (travel_in_corridor_m_ >= opt_.trust_memory_after_m || floor_edge_band_.has_value()))) &&
           std::abs(WrapPi(yaw - axis_yaw_odom_)) < DegToRad(45.0));
}

double Explorer::Free(const Percept& p, double yaw, double max_m, bool judging) const {
  const bool use_blocked = UseBlocked(yaw);
  // Where the floor there was seen they are ignored, unless the latest frame shows a brick wall's
  // lines (trust_memory_max_wall_lines).
  const bool seen_free_exempts =
      !(opt_.trust_memory_max_wall_lines > 0.0 && last_wall_lines_ >= opt_.trust_memory_max_wall_lines);
  const bool settled = opt_.settled_blocked_min_range_m > 0.0 && state_ == ExploreState::kFollow &&
                       travel_in_corridor_m_ >= opt_.trust_memory_after_m;
  double min_range_m = settled ? opt_.settled_blocked_min_range_m : 0.0;
  if (setting_off_ && opt_.setoff_blocked_min_range_m > 0.0) min_range_m = opt_.setoff_blocked_min_range_m;
  // Setting off where it stands, the robot keeps the near edges it held out of the view too.
  const double standing_m = setting_off_ ? opt_.setoff_standing_hold_m : 0.0;
  // shift_points_within_m: on the drive to a mouth's centre, a wall ranged on the way in.
  if (opt_.shift_points_within_m > 0.0 && ShiftingAfterTravel() && std::abs(WrapPi(yaw - axis_yaw_odom_)) < DegToRad(45.0)) {
    const double points = memory_.PointsFreeTravel(p.odom_T_robot, yaw, opt_.robot_radius_m + opt_.safety_margin_m, max_m,
                                                   0.0, 0.0, /*kept_edges=*/!judging);
    if (points < opt_.shift_points_within_m) return points;
  }
  return memory_.FreeTravel(p.odom_T_robot, yaw, opt_.robot_radius_m + opt_.safety_margin_m, max_m, use_blocked,
                            seen_free_exempts, min_range_m, standing_m, /*kept_edges=*/!judging);
}

double Explorer::FreeAcross(const Percept& p, double side_yaw, double line_m) const {
  const double max_m = opt_.branch_depth_m + 0.5;
  if (line_m < 0.0) return Free(p, side_yaw, max_m, /*judging=*/true);
  // As Free (the remembered points only: the latest scan looks ahead, not across), leaving out the
  // band beyond the armed side's wall line where a floor edge seen through the opening lies.
  return memory_.PointsFreeTravel(p.odom_T_robot, side_yaw, opt_.robot_radius_m + opt_.safety_margin_m, max_m,
                                  line_m + opt_.branch_line_tolerance_m, line_m + opt_.branch_line_band_m,
                                  /*kept_edges=*/false, opt_.branch_coarse_from_m);
}

double Explorer::SideLineTravel(double yaw, double left_m, double right_m) const {
  const double lateral_rate = std::sin(WrapPi(yaw - axis_yaw_odom_));  // left positive
  const double wall_m = lateral_rate > 0.0 ? left_m : lateral_rate < 0.0 ? right_m : -1.0;
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (!(wall_m > 0.0)) return kNone;
  // A line the robot's centre would not reach within the lookahead closes nothing.
  if (wall_m / std::abs(lateral_rate) > opt_.lookahead_m + opt_.robot_radius_m) return kNone;
  return std::max(0.0, wall_m - opt_.robot_radius_m - opt_.safety_margin_m) / std::abs(lateral_rate);
}

double Explorer::BestGap(const Percept& p, double desired_yaw, double* free, double left_m, double right_m) const {
  double best_yaw = desired_yaw;
  double best_score = -1e9;
  double best_free = 0.0;
  for (int k = -opt_.gap_steps; k <= opt_.gap_steps; ++k) {
    // Candidates in the order 0, -1, +1, -2, ... are not needed: the score breaks ties by angle.
    const double off_deg = k * opt_.gap_step_deg;
    const double yaw = WrapPi(desired_yaw + DegToRad(off_deg));
    const double f = std::min(Free(p, yaw, opt_.lookahead_m), SideLineTravel(yaw, left_m, right_m));
    const double score = f / opt_.lookahead_m - opt_.gap_cost_per_deg * std::abs(off_deg);
    if (score > best_score) {
      best_score = score;
      best_yaw = yaw;
      best_free = f;
    }
  }
  *free = best_free;
  return best_yaw;
}

Command Explorer::Guard(const Percept& p, Command cmd) {
  if (!sonar_seen_ || cmd.v_mps == 0.0) return cmd;
  if (cmd.v_mps > 0.0) {
    // Forward only into what a scan has seen from (about) this heading.
    if (std::abs(WrapPi(p.odom_T_robot.yaw - last_scan_yaw_)) > DegToRad(opt_.rescan_yaw_deg)) {
      ++speed_limited_;
      return {0.0, cmd.omega_rps};
    }
    // Nothing unknown beside the path, where the camera does not look.
    if (opt_.guard_unknown_step_m > 0.0 && odometer_m_ >= opt_.guard_unknown_after_m &&
        memory_.UnknownBeside(p.odom_T_robot, p.odom_T_robot.yaw, opt_.robot_radius_m, opt_.guard_unknown_step_m,
                              opt_.guard_unknown_inner_m, p.stamp_s)) {
      return {0.0, cmd.omega_rps};
    }
    // The disc's free travel along the heading now and the heading half a second on.
    const double yaw_ahead = WrapPi(p.odom_T_robot.yaw + 0.5 * cmd.omega_rps);
    const double free = std::min(Free(p, p.odom_T_robot.yaw, opt_.lookahead_m), Free(p, yaw_ahead, opt_.lookahead_m));
    const double vmax = std::max(0.0, opt_.speed_per_free_mps * (free - opt_.stop_margin_m));
    if (cmd.v_mps > vmax) {
      ++speed_limited_;
      cmd.v_mps = vmax;
    }
  } else {
    const double free = Free(p, WrapPi(p.odom_T_robot.yaw + kPi), 1.0);
    const double vmax = std::max(0.0, opt_.speed_per_free_mps * (free - opt_.stop_margin_m));
    if (-cmd.v_mps > vmax) cmd.v_mps = -vmax;
  }
  return cmd;
}

void Explorer::UpdateMapPose(const Percept& p, const Pose2& delta) {
  const double ds = delta.x;  // forward travel (signed); unicycle: no sideways motion
  const double yaw = WrapPi(p.odom_T_robot.yaw - map_yaw_offset_);
  const double mid = WrapPi(yaw - 0.5 * delta.yaw);
  map_pose_.x += ds * std::cos(mid);
  map_pose_.y += ds * std::sin(mid);
  map_pose_.yaw = yaw;
  odometer_m_ += std::abs(ds);
  if (state_ == ExploreState::kFollow) {
    travel_in_corridor_m_ += std::abs(ds);
    if (travel_in_corridor_m_ >= opt_.trust_memory_after_m) setting_off_ = false;
    if (dist_end_m_ >= 0.0) dist_end_m_ = std::max(0.0, dist_end_m_ - ds * std::cos(WrapPi(p.odom_T_robot.yaw - axis_yaw_odom_)));
  }
  last_odom_ = p.odom_T_robot;
}

bool Explorer::Rotate(const Percept& p, Rotation& r, Command& cmd) const {
  const double err = WrapPi(r.target_yaw - p.odom_T_robot.yaw);
  cmd = {};
  if (std::abs(err) > DegToRad(opt_.turn_tolerance_deg)) {
    double w = std::clamp(2.5 * err, -opt_.turn_rate_rps, opt_.turn_rate_rps);
    if (std::abs(w) < 0.15) w = std::copysign(0.15, err);
    cmd.omega_rps = w;
    r.settle = 0;
    return false;
  }
  return ++r.settle > opt_.settle_frames;
}

// --- Scan -------------------------------------------------------------------------------------

Command Explorer::ScanStep(const Percept& p) {
  const int bins = opt_.scan_bins;
  constexpr double kScanReachM = 3.0;  // the free travel the scan's choice looks for (metres)
  if (scan_rotating_) {
    const double rel = WrapPi(p.odom_T_robot.yaw - scan_start_yaw_);
    const double u = (rel < 0 ? rel + 2 * kPi : rel) / (2 * kPi);
    const int b = std::clamp(static_cast<int>(u * bins), 0, bins - 1);
    if (p.glance_entropy_nats) {
      scan_sum_[b] += *p.glance_entropy_nats;
      ++scan_count_[b];
    }
    if (p.sonar != nullptr) {
      ++scan_views_[b];
      if (view_is_wall_ || (opt_.scan_wall_lines > 0.0 && p.sonar_wall_lines >= opt_.scan_wall_lines)) ++scan_wall_views_[b];
    }
    // The axis a heading reading implies, modulo 90° in [0, π/2).
    auto axis_mod90 = [&](double heading_deg) { return std::fmod(p.odom_T_robot.yaw - DegToRad(heading_deg) + 8 * kPi, kPi / 2); };
    if (p.processed && p.heading_deg) scan_axis_mod90_.push_back(axis_mod90(*p.heading_deg));
    if (WantsAlignLines() && p.wall_line_heading_deg) scan_line_axis_mod90_.push_back(axis_mod90(*p.wall_line_heading_deg));
    // Progress of the full turn from the yaw travelled (odometry).
    scan_turned_ += std::abs(WrapPi(p.odom_T_robot.yaw - scan_prev_yaw_));
    scan_prev_yaw_ = p.odom_T_robot.yaw;
    if (scan_turned_ < 2 * kPi + DegToRad(360.0 / bins)) return {0.0, opt_.scan_rate_rps};
    // The scan bin a yaw falls in.
    auto bin_of = [&](double yaw) {
      const double from_start = WrapPi(yaw - scan_start_yaw_);
      return static_cast<int>(std::floor((from_start < 0 ? from_start + 2 * kPi : from_start) / (2 * kPi) * bins)) % bins;
    };
    // Mean glance entropy around a yaw (circular window of ±1 bin).
    auto entropy_at = [&](double yaw) {
      const int c = bin_of(yaw);
      double s = 0.0;
      int n = 0;
      for (int k = -1; k <= 1; ++k) {
        const int j = (c + k + bins) % bins;
        s += scan_sum_[j];
        n += scan_count_[j];
      }
      return n > 0 ? s / n : -1.0;
    };
    // Free travel for the choice: none where the sonar's views around the yaw (+-1 bin) were
    // mostly a wall filling the view. Such a wall stands inside the blind range: its columns are
    // blocked near and never remembered, so the memory alone finds that direction the freest
    // (corridor-6 start 2: 0.1 m from a wall, the start-up scan set off into it).
    auto scan_free = [&](double yaw) {
      if (opt_.scan_skips_wall_views) {
        const int c = bin_of(yaw);
        int views = 0, walls = 0;
        for (int k = -1; k <= 1; ++k) {
          views += scan_views_[static_cast<std::size_t>((c + k + bins) % bins)];
          walls += scan_wall_views_[static_cast<std::size_t>((c + k + bins) % bins)];
        }
        if (views > 0 && 2 * walls > views) return 0.0;
      }
      return Free(p, yaw, kScanReachM);
    };
    // The Manhattan axis modulo 90°: the mode of the candidates (2° bins, ±2 bins smoothing).
    auto mode_mod90 = [](const std::vector<double>& candidates) {
      constexpr int kBins = 45;
      std::array<double, kBins> hist{};
      for (double a : candidates) hist[static_cast<std::size_t>(std::clamp(static_cast<int>(a / (kPi / 2) * kBins), 0, kBins - 1))] += 1.0;
      int best_i = 0;
      double best_v = -1.0;
      for (int i = 0; i < kBins; ++i) {
        double v = 0.0;
        for (int k = -2; k <= 2; ++k) v += hist[static_cast<std::size_t>((i + k + kBins) % kBins)] * (k == 0 ? 1.0 : 0.5);
        if (v > best_v) {
          best_v = v;
          best_i = i;
        }
      }
      // Refine: circular mean of the candidates within ±4° of the mode (period 90°).
      const double centre = (best_i + 0.5) * (kPi / 2) / kBins;
      double sx = 0.0, sy = 0.0;
      for (double a : candidates) {
        if (std::abs(WrapPi(4.0 * (a - centre))) / 4.0 > DegToRad(4.0)) continue;
        sx += std::cos(4.0 * a);
        sy += std::sin(4.0 * a);
      }
      return (sx != 0.0 || sy != 0.0) ? std::atan2(sy, sx) / 4.0 : centre;
    };
    double axis_mod = 0.0;
    bool have_axis = scan_axis_mod90_.size() >= 5;
    if (have_axis) axis_mod = mode_mod90(scan_axis_mod90_);
    // The walls the memory holds outvote a glance axis that disagrees with them.
    double wall_axis = 0.0;
    if (WallAxis(&wall_axis)) {
      if (!have_axis || std::abs(std::remainder(wall_axis - axis_mod, kPi / 2)) > DegToRad(10.0)) axis_mod = wall_axis;
      have_axis = true;
    }
    // The walls' lines, where they read, outvote both (wall_line_align_over_deg: only where they
    // disagree by more than that, or where the others give no axis).
    if (scan_line_axis_mod90_.size() >= 5) {
      const double line_mod = mode_mod90(scan_line_axis_mod90_);
      if (LinesOverride(have_axis ? RadToDeg(std::abs(std::remainder(line_mod - axis_mod, kPi / 2))) : 90.0)) axis_mod = line_mod;
      have_axis = true;
    }
    double best_yaw = scan_start_yaw_;
    if (have_axis) {
      // scan_entropy_floor: a direction the memory finds free to the scan's full reach (nothing
      // ranged there: a wall inside the blind range may be forgotten) with too little entropy for
      // a corridor view is not taken.
      std::array<double, 4> entropy{};
      double top_entropy = 0.0;
      for (int k = 0; k < 4; ++k) {
        entropy[static_cast<std::size_t>(k)] = entropy_at(WrapPi(axis_mod + k * kPi / 2));
        top_entropy = std::max(top_entropy, entropy[static_cast<std::size_t>(k)]);
      }
      std::array<double, 4> free{}, score{};
      std::array<bool, 4> skipped{};
      for (int k = 0; k < 4; ++k) {
        const auto i = static_cast<std::size_t>(k);
        free[i] = scan_free(WrapPi(axis_mod + k * kPi / 2));
        // With the sonar the free travel decides (metres dominate), entropy breaks ties.
        score[i] = entropy[i] + (sonar_seen_ ? 10.0 * free[i] : 0.0);
        skipped[i] = opt_.scan_entropy_floor > 0.0 && entropy[i] < opt_.scan_entropy_floor * top_entropy && free[i] >= kScanReachM;
      }
      // scan_wall_entropy: a direction with a wall's entropy is not taken while another (not
      // skipped by the floor) is left.
      std::array<bool, 4> wall_view{};
      bool other_left = false;
      for (std::size_t i = 0; i < 4; ++i) {
        wall_view[i] = opt_.scan_wall_entropy > 0.0 && entropy[i] < opt_.scan_wall_entropy * top_entropy;
        other_left = other_left || (!skipped[i] && !wall_view[i]);
      }
      if (!other_left) wall_view.fill(false);
      // The first direction of the highest score above -1 among those not left out (-1: none).
      const auto argmax = [&score](const std::array<bool, 4>& out) {
        int at = -1;
        double top = -1.0;
        for (std::size_t i = 0; i < 4; ++i) {
          if (out[i] || !(score[i] > top)) continue;
          top = score[i];
          at = static_cast<int>(i);
        }
        return at;
      };
      const auto yaw_of = [&](int k) { return k < 0 ? scan_start_yaw_ : WrapPi(axis_mod + k * kPi / 2); };
      std::array<bool, 4> not_taken{};
      for (std::size_t i = 0; i < 4; ++i) not_taken[i] = skipped[i] || wall_view[i];
      const int any = argmax({});        // without the floor, to count the scans it changed
      const int kept = argmax(skipped);  // without scan_wall_entropy, to count the scans it changed
      const int taken = argmax(not_taken);
      best_yaw = yaw_of(taken);
      const bool best_any_skipped = any >= 0 && skipped[static_cast<std::size_t>(any)];
      const double best_kept_yaw = yaw_of(kept);
      if (best_any_skipped) ++scan_entropy_skips_;
      if (best_yaw != best_kept_yaw) ++scan_wall_entropy_skips_;
    } else {
      double best = -1.0;
      for (int i = 0; i < bins; ++i) {
        const double yaw = WrapPi(scan_start_yaw_ + (i + 0.5) * 2 * kPi / bins);
        const double h = entropy_at(yaw) + (sonar_seen_ ? 10.0 * scan_free(yaw) : 0.0);
        if (h > best) {
          best = h;
          best_yaw = yaw;
        }
      }
    }
    scan_rotating_ = false;
    last_ref_entropy_ = std::max(entropy_at(best_yaw), 0.0);
    scan_final_ = Rotation{best_yaw, 0};
  }
  Command cmd;
  if (!Rotate(p, scan_final_, cmd)) return cmd;
  state_ = ExploreState::kAlign;
  ClearAlignSamples();
  align_round_ = 0;
  align_rotating_ = false;
  return {};
}

// --- Align: stand still, read the fused heading, rotate it away ---------------------------------

Command Explorer::AlignStep(const Percept& p) {
  Command cmd;
  if (align_rotating_) {
    if (!Rotate(p, align_rot_, cmd)) return cmd;
    align_rotating_ = false;
    ClearAlignSamples();
    return {};
  }
  if (p.processed && p.heading_deg) align_samples_.push_back(*p.heading_deg);
  if (WantsAlignLines() && p.wall_line_heading_deg) align_line_samples_.push_back(*p.wall_line_heading_deg);
  if (!start_checked_ && p.glance_entropy_nats) {
    start_entropy_sum_ += *p.glance_entropy_nats;
    ++start_entropy_n_;
  }
  const bool enough = static_cast<int>(align_samples_.size()) >= opt_.align_frames;
  if (!start_checked_ && !enough && start_entropy_n_ < 3 * opt_.align_frames) return {};
  if (!enough && start_checked_ && align_round_ < opt_.align_rounds) return {};
  double median = 0.0;
  double spread = 0.0;
  if (!align_samples_.empty()) {
    std::vector<double> v = align_samples_;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    median = v[v.size() / 2];
    for (double& x : v) x = std::abs(x - median);
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    spread = v[v.size() / 2];
  }
  if (!start_checked_) {
    start_checked_ = true;
    const double mean_entropy = start_entropy_n_ > 0 ? start_entropy_sum_ / start_entropy_n_ : 0.0;
    if (!enough || mean_entropy < opt_.start_corridor_entropy_nats || spread > opt_.start_max_spread_deg ||
        std::abs(median) > opt_.axis_outlier_deg || (opt_.scan_blind_start && last_scan_blind_)) {
      state_ = ExploreState::kScan;  // not a corridor view: turn around in place and look
      ClearAlignSamples();
      return {};
    }
    last_ref_entropy_ = mean_entropy;
  }
  // The walls' lines, where they read (at least 3 views, two in three within 2° of their median),
  // give the heading modulo 90° exactly: the glance's median moves to the nearest such heading.
  if (static_cast<int>(align_line_samples_.size()) >= 3) {
    const double ref = align_line_samples_.front();
    std::vector<double> d;
    for (double h : align_line_samples_) d.push_back(RadToDeg(std::remainder(DegToRad(h - ref), kPi / 2)));
    std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
    const double mid = d[d.size() / 2];
    const auto near = std::count_if(d.begin(), d.end(), [&](double x) { return std::abs(x - mid) <= 2.0; });
    if (3 * near >= 2 * static_cast<std::ptrdiff_t>(d.size())) {
      const double line = ref + mid;
      const double nearest = line + 90.0 * std::round((median - line) / 90.0);
      if (LinesOverride(std::abs(nearest - median))) {
        // Far from the glance's median (which of the four the axis is, the glance cannot tell):
        // look all around once, the lines giving the axis and the free travel the direction.
        if (std::abs(nearest - median) > kAlignLineAgreeDeg && !align_line_scanned_) {
          align_line_scanned_ = true;
          StartScan(p);
          return {};
        }
        median = nearest;
      }
    }
  }
  if (align_round_ < opt_.align_rounds && std::abs(median) > opt_.align_done_deg) {
    ++align_round_;
    align_rot_ = Rotation{WrapPi(p.odom_T_robot.yaw - DegToRad(median)), 0};
    align_rotating_ = true;
    return {};
  }
  axis_yaw_odom_ = WrapPi(p.odom_T_robot.yaw - DegToRad(median));
  if (rescan_) {
    // A recovery scan: keep the map frame, take the map direction nearest to the new axis.
    rescan_ = false;
    dir_ = DirectionOfYaw(WrapPi(axis_yaw_odom_ - map_yaw_offset_));
    map_yaw_offset_ = WrapPi(axis_yaw_odom_ - YawOfDirection(dir_));
  } else {
    map_yaw_offset_ = axis_yaw_odom_;
    dir_ = 0;
  }
  Emit(ExploreEvent::Kind::kScanDone, p, 0,
       Format("set off at odometry yaw %.0f deg after %d alignment rounds", RadToDeg(axis_yaw_odom_), align_round_));
  align_line_scanned_ = false;
  StartFollow(p);
  return {};
}

bool Explorer::LinesOverride(double disagree_deg) {
  if (opt_.wall_line_align) return true;
  if (!(disagree_deg > opt_.wall_line_align_over_deg)) return false;
  ++align_line_overrides_;
  return true;
}

void Explorer::ClearAlignSamples() {
  align_samples_.clear();
  align_line_samples_.clear();
}

void Explorer::StartScan(const Percept& p) {
  state_ = ExploreState::kScan;
  setting_off_ = true;
  scan_axis_mod90_.clear();
  scan_line_axis_mod90_.clear();
  std::fill(scan_sum_.begin(), scan_sum_.end(), 0.0);
  std::fill(scan_count_.begin(), scan_count_.end(), 0);
  std::fill(scan_views_.begin(), scan_views_.end(), 0);
  std::fill(scan_wall_views_.begin(), scan_wall_views_.end(), 0);
  scan_turned_ = 0.0;
  scan_start_yaw_ = scan_prev_yaw_ = p.odom_T_robot.yaw;
  scan_rotating_ = true;
}

// --- Follow -----------------------------------------------------------------------------------

void Explorer::StartFollow(const Percept&) {
  state_ = ExploreState::kFollow;
  end_count_ = 0;
  travel_in_corridor_m_ = 0.0;
  dist_end_m_ = -1.0;
  dist_hist_.clear();
  entropy_low_count_ = 0;
  outlier_axes_.clear();
  lateral_cue_deg_ = 0.0;
  lateral_valid_ = false;
  light_readings_.clear();
  light_drift_.clear();
  light_confirmed_s_ = -1.0;
  light_axis_s_ = -1.0;
  wall_line_readings_.clear();
  wall_line_axis_s_ = -1.0;
  ref_entropy_.clear();
  ref_next_ = 0;
  gate_reset_ = true;
  heading_filter_reset_ = true;
  heading_filter_prior_ = true;
  stall_.Reset();
  sides_[0] = sides_[1] = SideTrack{};
  last_wall_m_[0] = last_wall_m_[1] = -1.0;
}

void Explorer::UpdateAxis(const Percept& p) {
  if (!p.processed || !p.heading_deg) return;
  const double measured_axis = p.odom_T_robot.yaw - DegToRad(*p.heading_deg);
  const double innovation = WrapPi(measured_axis - axis_yaw_odom_);
  if (std::abs(innovation) > DegToRad(opt_.axis_outlier_deg)) {
    outlier_axes_.push_back(innovation);
    if (static_cast<int>(outlier_axes_.size()) >= opt_.axis_reacquire_frames) {
      std::nth_element(outlier_axes_.begin(), outlier_axes_.begin() + static_cast<std::ptrdiff_t>(outlier_axes_.size() / 2), outlier_axes_.end());
      double by = outlier_axes_[outlier_axes_.size() / 2];
      // While the walls' lines hold the axis modulo 90°, a re-acquisition (a corner rounded) can
      // only turn it by a multiple of 90°; none at all, and the glance's outliers are dropped.
      if (WallLinesHold(p.stamp_s)) {
        by = kPi / 2 * std::round(by / (kPi / 2));
        if (by == 0.0) {
          outlier_axes_.clear();
          return;
        }
      }
      axis_yaw_odom_ = WrapPi(axis_yaw_odom_ + by);
      // Re-acquired near another map direction (the robot went round a corner without stopping):
      // drive on in that direction; the corridor just left has no known end node, so its edge
      // is dropped, and the side tracks start afresh.
      // The map frame is not turned by a re-acquisition (a corner's view can give a diagonal
      // axis); inlier updates refine it afterwards.
      const int new_dir = DirectionOfYaw(WrapPi(axis_yaw_odom_ - map_yaw_offset_));
      if (new_dir != dir_) {
        dir_ = new_dir;
        map_.CancelDeparture();
      }
      sides_[0] = sides_[1] = SideTrack{};  // walls seen in the old frame do not arm an opening
      light_readings_.clear();
      light_drift_.clear();
      light_confirmed_s_ = -1.0;
      outlier_axes_.clear();
      heading_filter_reset_ = true;
      heading_filter_prior_ = false;
    }
    return;
  }
  outlier_axes_.clear();
  // While the walls' lines steer the axis, the glance's inliers do not.
  if (WallLinesHold(p.stamp_s)) return;
  // While the lights' line steers the axis (light_axis_gain), the glance's inliers do not.
  if (SteeredWithin(opt_.light_axis_gain, light_axis_s_, p.stamp_s, opt_.light_hold_s)) return;
  // With the heading filter, an inlier moves the axis toward the filtered heading's axis.
  double gain = opt_.axis_gain;
  double step = innovation;
  if (opt_.filtered_axis_gain > 0.0 && p.heading_filtered_deg) {
    gain = opt_.filtered_axis_gain;
    step = WrapPi(p.odom_T_robot.yaw - DegToRad(*p.heading_filtered_deg) - axis_yaw_odom_);
  }
  axis_yaw_odom_ = WrapPi(axis_yaw_odom_ + gain * step);
  // The map frame follows the axis by the same innovation; it snaps to the axis only when they
  // agree within a few degrees (not after a re-acquisition onto a diagonal view).
  const double residual = WrapPi(axis_yaw_odom_ - YawOfDirection(dir_) - map_yaw_offset_);
  map_yaw_offset_ = std::abs(residual) < DegToRad(5.0) ? WrapPi(axis_yaw_odom_ - YawOfDirection(dir_))
                                                       : WrapPi(map_yaw_offset_ + gain * step);
}

double Explorer::ReferenceEntropy() const {
  if (static_cast<int>(ref_entropy_.size()) < kOwnReferenceSamples) return last_ref_entropy_;
  std::vector<double> v = ref_entropy_;
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(opt_.reference_percentile * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

Eigen::Vector2d Explorer::AxisLeft() const { return {-std::sin(axis_yaw_odom_), std::cos(axis_yaw_odom_)}; }

void Explorer::UpdateLight(const Percept& p) {
  if (opt_.light_centre_gain <= 0.0 || !p.light_lateral_m || !p.light_heading_deg) return;
  // Gated by the heading the explorer holds (a lit door frame or one row of two side rows fits a
  // line too, but seldom along the corridor) and by the corridor's plausible half-width.
  if (std::abs(*p.light_heading_deg - HeadingEstimateDeg()) > opt_.light_heading_gate_deg ||
      std::abs(*p.light_lateral_m) > opt_.light_max_lateral_m)
    return;
  const Eigen::Vector2d o = p.odom_T_robot.Translation();
  if (light_readings_.empty()) light_ref_ = o;
  light_readings_.push_back({p.stamp_s, *p.light_lateral_m + AxisLeft().dot(o - light_ref_)});
  if (static_cast<int>(light_readings_.size()) > opt_.light_confirm) light_readings_.erase(light_readings_.begin());
  if (static_cast<int>(light_readings_.size()) < opt_.light_confirm) return;
  // Confirmed when the last light_confirm readings, each within light_hold_s of the next, agree.
  std::vector<double> v;
  for (std::size_t i = 0; i < light_readings_.size(); ++i) {
    if (i > 0 && light_readings_[i].stamp_s - light_readings_[i - 1].stamp_s > opt_.light_hold_s) return;
    v.push_back(light_readings_[i].across_m);
  }
  std::sort(v.begin(), v.end());
  if (v.back() - v.front() > opt_.light_agree_m) return;
  light_across_m_ = v[v.size() / 2];
  light_confirmed_s_ = p.stamp_s;
}

void Explorer::UpdateLightDrift(const Percept& p) {
  if (opt_.light_drift_gain <= 0.0) return;
  const Eigen::Vector2d o = p.odom_T_robot.Translation();
  if (p.light_lateral_m && p.light_heading_deg &&
      std::abs(*p.light_heading_deg - HeadingEstimateDeg()) <= opt_.light_drift_gate_deg &&
      std::abs(*p.light_lateral_m) <= opt_.light_max_lateral_m)
    light_drift_.push_back({o, *p.light_lateral_m});
  if (light_drift_.empty()) return;
  // Keep the last light_drift_window_m of travel along the axis.
  const Eigen::Vector2d u(std::cos(axis_yaw_odom_), std::sin(axis_yaw_odom_));
  const Eigen::Vector2d n(-u.y(), u.x());
  std::size_t first = 0;
  while (first < light_drift_.size() && std::abs(u.dot(o - light_drift_[first].odom)) > opt_.light_drift_window_m) ++first;
  light_drift_.erase(light_drift_.begin(), light_drift_.begin() + static_cast<std::ptrdiff_t>(first));
  const std::size_t k = light_drift_.size();
  if (static_cast<int>(k) < opt_.light_drift_min_readings) return;
  // across − offset = c + δ · along: the line's direction is the axis turned by δ.
  double sa = 0.0, sb = 0.0, saa = 0.0, sab = 0.0, sbb = 0.0, lo = 1e300, hi = -1e300;
  for (const LightDrift& r : light_drift_) {
    const double a = u.dot(r.odom - o), b = n.dot(r.odom - o) - r.lateral_m;
    sa += a, sb += b, saa += a * a, sab += a * b, sbb += b * b;
    lo = std::min(lo, a), hi = std::max(hi, a);
  }
  if (hi - lo < opt_.light_drift_min_span_m) return;
  const double kk = static_cast<double>(k);
  const double var = saa - sa * sa / kk;  // centred sums of squares and products
  if (!(var > 0.0)) return;
  const double cov = sab - sa * sb / kk;
  const double slope = cov / var;
  const double ss = std::max(0.0, sbb - sb * sb / kk - slope * cov);  // the fit's squared residuals
  const double delta = std::atan(slope);
  if (std::sqrt(ss / kk) > opt_.light_drift_max_rms_m || std::abs(delta) > DegToRad(opt_.light_drift_max_deg)) return;
  RotateAxis(opt_.light_drift_gain * delta);
}

bool Explorer::LightLateral(double stamp_s, const Pose2& odom_T_robot, double* lateral_m) const {
  if (opt_.light_centre_gain <= 0.0 || light_confirmed_s_ < 0.0 || stamp_s - light_confirmed_s_ > opt_.light_hold_s)
    return false;
  *lateral_m = light_across_m_ - AxisLeft().dot(odom_T_robot.Translation() - light_ref_);
  return true;
}

bool Explorer::WallLinesHold(double stamp_s) const {
  return SteeredWithin(opt_.wall_line_axis_gain, wall_line_axis_s_, stamp_s, opt_.wall_line_hold_s);
}

std::optional<double> Explorer::WallLineAxisDiff(const Percept& p) const {
  if (!p.wall_line_heading_deg) return std::nullopt;
  const double raw = WrapPi(p.odom_T_robot.yaw - DegToRad(*p.wall_line_heading_deg));
  const double diff = std::remainder(raw - axis_yaw_odom_, kPi / 2);
  if (std::abs(diff) > DegToRad(opt_.wall_line_gate_deg)) return std::nullopt;
  return diff;
}

void Explorer::UpdateWallLines(const Percept& p) {
  if (opt_.wall_line_axis_gain <= 0.0) return;
  const std::optional<double> axis_diff = WallLineAxisDiff(p);
  if (!axis_diff) return;
  const double diff = *axis_diff;
  if (!wall_line_readings_.empty() && p.stamp_s - wall_line_readings_.back().stamp_s > opt_.wall_line_hold_s)
    wall_line_readings_.clear();
  wall_line_readings_.push_back({p.stamp_s, WrapPi(axis_yaw_odom_ + diff)});
  if (static_cast<int>(wall_line_readings_.size()) > opt_.wall_line_confirm) wall_line_readings_.erase(wall_line_readings_.begin());
  if (static_cast<int>(wall_line_readings_.size()) < opt_.wall_line_confirm) return;
  // Agreement, as differences from the newest (all near the axis held, so no wrap across ±π/4).
  std::vector<double> d;
  for (const WallLineReading& r : wall_line_readings_) d.push_back(WrapPi(r.axis_rad - wall_line_readings_.back().axis_rad));
  std::sort(d.begin(), d.end());
  if (d.back() - d.front() > DegToRad(opt_.wall_line_agree_deg)) return;
  const double to_target = WrapPi(wall_line_readings_.back().axis_rad + d[d.size() / 2] - axis_yaw_odom_);
  if (std::abs(to_target) < DegToRad(opt_.wall_line_min_diff_deg)) return;
  RotateAxis(opt_.wall_line_axis_gain * to_target);
  wall_line_axis_s_ = p.stamp_s;
}

void Explorer::NoteWallLinesAhead(const Percept& p) {
  if (!p.wall_line_corridor_ahead_m) return;  // no frame for the lines this step
  const double ahead = WallLineAxisDiff(p) ? *p.wall_line_corridor_ahead_m : 0.0;
  std::erase_if(wall_line_ahead_, [&](const WallLineAhead& r) { return p.stamp_s - r.stamp_s > kWallLineAheadHoldS; });
  wall_line_ahead_.push_back({p.stamp_s, p.odom_T_robot.yaw, ahead});
}

bool Explorer::WallLinesFree(const Percept& p, double yaw) const {
  if (opt_.wall_line_free_m <= 0.0) return false;
  int facing = 0, free = 0;
  for (const WallLineAhead& r : wall_line_ahead_) {
    if (p.stamp_s - r.stamp_s > kWallLineAheadHoldS || std::abs(WrapPi(r.yaw - yaw)) > DegToRad(kWallLineAheadYawDeg)) continue;
    ++facing;
    free += r.ahead_m >= opt_.wall_line_free_m ? 1 : 0;
  }
  return facing > 0 && 2 * free >= facing;
}

bool Explorer::WallKeep(const Percept& p, double* target_rel_axis) {
  if (opt_.wall_keep_m <= 0.0 || (opt_.wall_keep_setoff_only && !setting_off_)) return false;
  if (p.wall_line_offset_m && p.wall_line_direction_deg) {
    WallKeepReading& r = wall_keep_reading_;
    r.stamp_s = p.stamp_s;
    r.odom_T_robot = p.odom_T_robot;
    r.direction_rad = DegToRad(*p.wall_line_direction_deg);
    r.offsets_m[0] = *p.wall_line_offset_m;
    r.lines = 1;
    if (p.wall_line_parallel_offset_m) r.offsets_m[r.lines++] = *p.wall_line_parallel_offset_m;
  }
  const WallKeepReading& r = wall_keep_reading_;
  if (r.stamp_s < 0.0 || p.stamp_s - r.stamp_s > 0.5) return false;
  // The line's direction in the odometry frame as read, and the one of its two senses nearest the axis.
  const double read_yaw = r.odom_T_robot.yaw + r.direction_rad;
  double line_yaw = WrapPi(read_yaw);
  if (std::abs(WrapPi(line_yaw - axis_yaw_odom_)) > kPi / 2) line_yaw = WrapPi(line_yaw + kPi);
  if (std::abs(WrapPi(line_yaw - axis_yaw_odom_)) > DegToRad(opt_.wall_keep_gate_deg)) return false;
  // Each line's signed distance from the robot now (left of the line's direction positive).
  const Eigen::Vector2d n(-std::sin(line_yaw), std::cos(line_yaw));
  const Eigen::Vector2d n_read(-std::sin(read_yaw), std::cos(read_yaw));
  double nearest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < r.lines; ++i) {
    const Eigen::Vector2d on_line = r.odom_T_robot.Translation() + r.offsets_m[i] * n_read;
    const double d = n.dot(on_line - p.odom_T_robot.Translation());
    if (std::abs(d) < opt_.wall_keep_min_m) continue;
    if (std::abs(d) < std::abs(nearest)) nearest = d;
  }
  if (!(std::abs(nearest) < opt_.wall_keep_m)) return false;
  const double push = std::min(opt_.wall_keep_max_deg, opt_.wall_keep_gain_deg_per_m * (opt_.wall_keep_m - std::abs(nearest)));
  // Away from the wall: right of the line's direction for a wall on the left.
  const double bound = WrapPi(line_yaw - std::copysign(DegToRad(push), nearest) - axis_yaw_odom_);
  const double t = *target_rel_axis;
  const double kept = nearest > 0.0 ? std::min(t, bound) : std::max(t, bound);
  if (kept == t) return false;
  *target_rel_axis = kept;
  ++wall_keep_frames_;
  return true;
}

Command Explorer::FollowStep(const Percept& p) {
  UpdateWallLines(p);
  UpdateAxis(p);
  if (opt_.light_axis_gain > 0.0 && p.light_heading_deg) {
    // The axis the lights' line implies (odometry yaw − its heading), near the one held.
    const double diff = DegToRad(HeadingEstimateDeg() - *p.light_heading_deg);
    if (std::abs(diff) <= DegToRad(opt_.light_axis_gate_deg)) {
      RotateAxis(opt_.light_axis_gain * diff);
      light_axis_s_ = p.stamp_s;
    }
  }
  UpdateLight(p);
  UpdateLightDrift(p);
  double wall_axis = 0.0;
  if (p.sonar != nullptr && travel_in_corridor_m_ > 1.0 && WallAxis(&wall_axis)) {
    // The walls the memory holds pull a drifted axis back (the glance's heading drifts at a T).
    const double diff = std::remainder(wall_axis - axis_yaw_odom_, kPi / 2);
    if (std::abs(diff) > DegToRad(8.0)) RotateAxis(opt_.wall_axis_gain * diff);
  }
  if (p.processed && p.heading_deg && p.centre_heading_deg) {
    const double meas = std::clamp(*p.centre_heading_deg - *p.heading_deg, -30.0, 30.0);
    lateral_cue_deg_ = lateral_valid_ ? lateral_cue_deg_ + opt_.centre_filter * (meas - lateral_cue_deg_) : meas;
    lateral_valid_ = true;
  }
  // Reference entropy: looking down this corridor, sampled every ~0.15 m so the approach to the
  // end does not dominate.
  if (p.glance_entropy_nats && dist_end_m_ != 0.0) {
    const double sample_every_m = 0.15;
    if (ref_entropy_.empty() || travel_in_corridor_m_ >= sample_every_m * static_cast<double>(ref_next_ + 1)) {
      const std::size_t cap = static_cast<std::size_t>(opt_.reference_window);
      if (ref_entropy_.size() < cap) ref_entropy_.push_back(*p.glance_entropy_nats);
      else ref_entropy_[static_cast<std::size_t>(ref_next_) % cap] = *p.glance_entropy_nats;
      ++ref_next_;
    }
  }
  // The end of the corridor: (a) the fused distance, median of the last processed frames.
  const bool may_end = travel_in_corridor_m_ >= opt_.min_travel_before_end_m;
  bool end_now = false;
  if (p.processed && p.dist_end_m) {
    dist_hist_.push_back(std::max(0.0, *p.dist_end_m));
    if (static_cast<int>(dist_hist_.size()) > opt_.end_median_frames) dist_hist_.erase(dist_hist_.begin());
    std::vector<double> v = dist_hist_;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    dist_end_m_ = v[v.size() / 2];
    if (static_cast<int>(dist_hist_.size()) >= opt_.end_median_frames && dist_end_m_ < opt_.end_stop_dist_m && may_end) end_now = true;
  }
  // (c) the visual sonar: little free travel along the corridor and no way around.
  double axis_free = opt_.lookahead_m;
  bool end_by_sonar = false;
  if (sonar_seen_) {
    axis_free = Free(p, axis_yaw_odom_, opt_.lookahead_m, /*judging=*/true);
    double gap_free = 0.0;
    if (axis_free < opt_.sonar_end_free_m && may_end) {
      BestGap(p, axis_yaw_odom_, &gap_free);
      if (gap_free < opt_.sonar_end_gap_m) end_now = end_by_sonar = true;
      // The walls' lines show the corridor going on: the sonar's "blocked near" is the floor's grey.
      if (end_by_sonar && WallLinesFree(p, axis_yaw_odom_)) {
        end_now = end_by_sonar = false;
      }
    }
  }
  // (b) the glance entropy against the corridor's reference (with the sonar: only where the
  // sonar also sees something ahead, so that a dip of entropy mid-corridor does not stop it).
  const double ref = ReferenceEntropy();
  const bool entropy_may_end = may_end && (!sonar_seen_ || axis_free < opt_.lookahead_m);
  if (p.glance_entropy_nats && ref > 0.0 && *p.glance_entropy_nats < opt_.end_entropy_ratio * ref && entropy_may_end) ++entropy_low_count_;
  else entropy_low_count_ = 0;
  if (entropy_low_count_ >= opt_.end_confirm_frames) end_now = true;
  end_count_ = end_now ? opt_.end_confirm_frames : 0;
  if (end_count_ >= opt_.end_confirm_frames) {
    ++ends_;
    last_ref_entropy_ = ReferenceEntropy();
    node_ = map_.Arrive(map_pose_.Translation(), dir_, CameAlong());
    // Something the sonar sees standing close ahead blocks the way now, whatever the map
    // remembers of it (sonar_end_blocks_m).
    map_.SetBranch(node_, dir_, Branch::kWall, end_by_sonar && axis_free < opt_.sonar_end_blocks_m);
    Emit(ExploreEvent::Kind::kEndDetected, p, 0,
         Format("end: fused distance %.2f m, entropy %.2f of reference %.2f, sonar free %.2f m (%s)", dist_end_m_,
                p.glance_entropy_nats.value_or(-1.0), last_ref_entropy_, axis_free, end_by_sonar ? "sonar" : "entropy/distance"));
    StartProbe(/*at_end=*/true);
    return {};
  }
  // Side branches passed along the corridor (with the sonar): stop at a new one and probe.
  if (TrackSides(p)) return {};

  // Stall guard (odometry only): commanded forward for a while, the wheels did not move.
  if (stall_.Stalled(p.stamp_s, p.odom_T_robot.Translation(), opt_.stall_window_s, opt_.stall_min_progress_m)) {
    Emit(ExploreEvent::Kind::kStall, p, 0, "no wheel progress: backing off");
    stalled_since_start_ = true;
    state_ = ExploreState::kBackOff;
    // Reversing is blind (no camera behind): with the sonar the robot only turns in place.
    backoff_until_s_ = p.stamp_s + (sonar_seen_ ? 0.0 : 2.0);
    return {};
  }

  const double heading = WrapPi(p.odom_T_robot.yaw - axis_yaw_odom_);
  Command cmd;
  // Obstacles across the path in the region of interest override corridor following.
  if (ObstacleOverride(p, &cmd)) return cmd;
  double correction = lateral_valid_ ? std::clamp(-opt_.centre_gain * lateral_cue_deg_, -opt_.max_centre_correction_deg,
                                                  opt_.max_centre_correction_deg)
                                     : 0.0;
  double target = DegToRad(correction);
  if (sonar_seen_) {
    // Centring between the side walls the sonar remembers beside the robot (none when one side
    // is open), then the free heading nearest to the centring one.
    double left = -1.0, right = -1.0;
    memory_.SideDistances(p.odom_T_robot, axis_yaw_odom_, 0.5, opt_.sonar_centre_max_lateral_m, &left, &right);
    correction = 0.0;
    double light_lateral = 0.0;
    if (LightLateral(p.stamp_s, p.odom_T_robot, &light_lateral))
      correction = std::clamp(RadToDeg(-opt_.light_centre_gain * light_lateral), -opt_.max_centre_correction_deg,
                              opt_.max_centre_correction_deg);
    else if (left > 0.0 && right > 0.0)
      correction = std::clamp(RadToDeg(-opt_.sonar_centre_gain * 0.5 * (right - left)), -opt_.max_centre_correction_deg,
                              opt_.max_centre_correction_deg);
    const double desired_yaw = WrapPi(axis_yaw_odom_ + DegToRad(correction));
    double free = Free(p, desired_yaw, opt_.lookahead_m);
    double yaw = desired_yaw;
    if (free < opt_.lookahead_m) {
      const double near = opt_.gap_side_wall_max_m;
      yaw = BestGap(p, desired_yaw, &free, left <= near ? left : -1.0, right <= near ? right : -1.0);
    }
    target = WrapPi(yaw - axis_yaw_odom_);
    WallKeep(p, &target);
  }
  const double err = WrapPi(target - heading);
  cmd.omega_rps = std::clamp(opt_.heading_gain * err, -opt_.max_omega_rps, opt_.max_omega_rps);
  double frac = std::max(opt_.min_speed_fraction, 1.0 - std::abs(RadToDeg(err)) / opt_.slow_heading_deg);
  if (NearKnownEnd()) frac = opt_.min_speed_fraction;
  cmd.v_mps = opt_.cruise_speed_mps * frac;
  return cmd;
}

bool Explorer::NearKnownEnd() const {
  if (opt_.known_end_slow_m <= 0.0) return false;
  const double yaw = YawOfDirection(dir_);
  const Eigen::Vector2d along(std::cos(yaw), std::sin(yaw));
  const Eigen::Vector2d here = map_pose_.Translation();
  for (const TopoNode& n : map_.Nodes()) {
    // A dead end: walls ahead and on both sides (an L corner or a T's bar has a way on).
    const auto wall = [&](int d) { return n.branch[static_cast<std::size_t>(d & 3)] == Branch::kWall; };
    if (!(wall(dir_) && wall(dir_ + 1) && wall(dir_ + 3))) continue;
    const Eigen::Vector2d rel = n.position_m - here;
    const double ahead = rel.dot(along);
    const double across = std::abs(rel.x() * along.y() - rel.y() * along.x());
    if (!(ahead > -1.0 && ahead < opt_.known_end_slow_m && across < opt_.map.merge_radius_m)) continue;
    if (opt_.known_end_disagree_m > 0.0 && !(dist_end_m_ > std::max(0.0, ahead) + opt_.known_end_disagree_m)) continue;
    return true;
  }
  return false;
}

// --- Obstacle override (the obstacle pipeline's advice) ----------------------------------------

bool Explorer::ObstacleOverride(const Percept& p, Command* cmd) {
  if (p.obstacles) {
    avoid_advice_ = *p.obstacles;
    avoid_stamp_s_ = p.stamp_s;
    avoid_yaw_ = p.odom_T_robot.yaw;
    avoid_blocked_count_ = avoid_advice_.in_path && avoid_advice_.blocked ? avoid_blocked_count_ + 1 : 0;
    avoid_in_path_count_ = avoid_advice_.in_path ? avoid_in_path_count_ + 1 : 0;
  }
  if (avoid_stamp_s_ < 0.0 || p.stamp_s - avoid_stamp_s_ > opt_.avoid_hold_s || !avoid_advice_.in_path) {
    if (avoid_stamp_s_ >= 0.0 && p.stamp_s - avoid_stamp_s_ > opt_.avoid_hold_s) avoid_in_path_count_ = avoid_blocked_count_ = 0;
    return false;
  }
  if (avoid_in_path_count_ < opt_.avoid_confirm_advices) return false;
  ++avoid_overrides_;
  if (avoid_advice_.blocked) {
    *cmd = {};
    if (avoid_blocked_count_ < opt_.avoid_blocked_frames) return true;  // stop, wait for confirmation
    // Stop and turn: look to both sides and choose, as at a blockage (kBackOff with no reversing).
    ++avoid_stops_;
    avoid_blocked_count_ = 0;
    avoid_stamp_s_ = -1.0;
    Emit(ExploreEvent::Kind::kStall, p, 0,
         Format("obstacle %.2f m ahead and no free gap: stop and turn", avoid_advice_.nearest_in_path_m));
    state_ = ExploreState::kBackOff;
    backoff_until_s_ = p.stamp_s;
    return true;
  }
  // Steer toward the widest free gap, its direction held in the odometry frame between advices.
  const double err = WrapPi(avoid_yaw_ + DegToRad(avoid_advice_.steer_deg) - p.odom_T_robot.yaw);
  cmd->omega_rps = std::clamp(opt_.avoid_gain * err, -opt_.max_omega_rps, opt_.max_omega_rps);
  cmd->v_mps = opt_.cruise_speed_mps * opt_.avoid_speed_fraction;
  return true;
}

// --- Side branches met while following ---------------------------------------------------------

bool StartsNewWallRun(const SideTrack& track, double travel_m, const ExplorerOptions& options) {
  // A gap already handled (a door recess rejected, or a junction) starts one however short it
  // was, else the run it interrupted stays consumed until the wall's next long break.
  return track.wall_first_m < 0.0 || travel_m - track.wall_last_m > options.branch_wall_gap_m ||
         (options.rearm_after_gap && track.consumed);
}

bool Explorer::TrackSides(const Percept& p) {
  if (!opt_.detect_branches || !sonar_seen_ || p.sonar == nullptr) return false;
  double wall[2] = {-1.0, -1.0};
  memory_.SideDistances(p.odom_T_robot, axis_yaw_odom_, opt_.side_window_m, opt_.side_wall_max_lateral_m, &wall[0],
                        &wall[1], opt_.side_wall_cluster_m);
  const double t = travel_in_corridor_m_;
  const Eigen::Vector2d o = p.odom_T_robot.Translation();
  const Eigen::Vector2d d(std::cos(axis_yaw_odom_), std::sin(axis_yaw_odom_));
  // Each side's outward normal, the robot's outward offset from the run's start, and where an
  // armed side's wall line lies from the robot (< 0: no line, every reading is that wall).
  const Eigen::Vector2d normal[2] = {AxisLeft(), -AxisLeft()};
  double line_at[2] = {-1.0, -1.0};
  for (int k = 0; k < 2; ++k) {
    const SideTrack& tr = sides_[k];
    if (opt_.branch_line_tolerance_m <= 0.0 || !tr.armed ||
        static_cast<int>(tr.line.size()) < opt_.branch_line_samples)
      continue;
    std::vector<double> v = tr.line;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    line_at[k] = v[v.size() / 2] - normal[k].dot(o - tr.ref);
    // Beyond the line: not this wall.
    if (wall[k] > line_at[k] + opt_.branch_line_tolerance_m) wall[k] = -1.0;
  }
  // The nearest remembered point ahead on each side (beyond the abeam window): an opening's far
  // edge (the next wall, the branch's far corner, or the end wall).
  double ahead[2] = {-1.0, -1.0};
  const std::vector<Eigen::Vector2d>& gathered = memory_.Gathered();
  const std::vector<double>& seen_from = memory_.GatheredSeenRanges();
  for (std::size_t i = 0; i < gathered.size(); ++i) {
    const Eigen::Vector2d q = gathered[i] - o;
    const double s = q.dot(d);
    if (s <= opt_.side_window_m) continue;
    const double l = d.x() * q.y() - d.y() * q.x();
    if (std::abs(l) < opt_.robot_radius_m || std::abs(l) > opt_.side_wall_max_lateral_m + 1.5) continue;
    const int k = l > 0.0 ? 0 : 1;
    // Beyond an armed side's wall line: a floor edge seen through the opening (within the band),
    // or with far_edge_on_line anything inside the branch (the far edge lies on the line), or with
    // branch_coarse_from_m a point seen only from afar (a branch's far wall ranged short).
    if (line_at[k] > 0.0 && std::abs(l) > line_at[k] + opt_.branch_line_tolerance_m &&
        (opt_.far_edge_on_line || std::abs(l) <= line_at[k] + opt_.branch_line_band_m ||
         (opt_.branch_coarse_from_m > 0.0 && seen_from[i] > opt_.branch_coarse_from_m)))
      continue;
    double& a = ahead[k];
    if (a < 0.0 || s < a) a = s;
  }
  for (int k = 0; k < 2; ++k) {
    SideTrack& tr = sides_[k];
    if (wall[k] > 0.0) {
      last_wall_m_[k] = wall[k];
      last_wall_at_[k] = o;
      if (StartsNewWallRun(tr, t, opt_)) {
        // A new run of wall (after a gap, or the first): an opening must follow a full run.
        tr = SideTrack{};
        tr.wall_first_m = t;
        tr.ref = o;
      }
      tr.wall_last_m = t;
      if (t - tr.wall_first_m >= opt_.branch_wall_before_m) tr.armed = true;
      if (opt_.branch_line_tolerance_m > 0.0 &&
          (opt_.branch_line_spacing_m <= 0.0 || t - tr.line_last_m >= opt_.branch_line_spacing_m)) {
        tr.line_last_m = t;
        tr.line.push_back(wall[k] + normal[k].dot(o - tr.ref));
        if (static_cast<int>(tr.line.size()) > opt_.branch_line_samples) tr.line.erase(tr.line.begin());
      }
      continue;
    }
    if (!tr.armed || tr.consumed) continue;
    const double edge = tr.wall_last_m - opt_.side_window_m;  // where the wall ended
    if (ahead[k] > 0.0) tr.far_m = t + ahead[k];
    const double width = tr.far_m > 0.0 ? tr.far_m - edge : opt_.branch_default_width_m;
    if (width < opt_.branch_min_width_m || width > opt_.branch_max_width_m) {
      tr.consumed = true;  // a door recess, or no wall beyond (an open area): not a side branch
      continue;
    }
    if (t < edge + 0.5 * width || t - tr.wall_last_m < opt_.branch_wall_gap_m) continue;
    // Not while steering well off the axis (round an obstacle, or a corner taken without a stop):
    // the stop and the probe need the corridor frame.
    if (std::abs(WrapPi(p.odom_T_robot.yaw - axis_yaw_odom_)) > DegToRad(opt_.branch_max_heading_deg)) continue;
    // At the opening's centre: a branch when free across for branch_depth_m.
    tr.consumed = true;
    const double side_yaw = WrapPi(axis_yaw_odom_ + (k == 0 ? 0.5 : -0.5) * kPi);
    if (FreeAcross(p, side_yaw, line_at[k]) < opt_.branch_depth_m) continue;
    // A crossing: the other side's opening is handled by the same stop (the probe looks at both).
    SideTrack& other = sides_[1 - k];
    const bool crossing = other.armed && wall[1 - k] <= 0.0;
    if (crossing) other.consumed = true;
    if (OnOpening(p, k, width)) {
      if (opt_.branch_line_tolerance_m > 0.0 && gap_side_dir_ >= 0) {
        // Past a floor edge the sonar may not show either side free from the mouth: each side
        // whose wall line ended here is open when the entropy rule says so, and its band is
        // cleared if the robot turns into it.
        auto record = [&](int side, int dir, double line) {
          if (line <= 0.0) return;
          // Along the axis from the robot: the opening from where this side's wall run ended.
          double a0 = -(0.5 * width + opt_.side_window_m), a1 = -a0;
          if (opt_.floor_edge_band_mouth) {
            a0 = WallRunEndAlong(side);
            a1 = a0 + width;
          }
          floor_edge_candidates_[side] =
              FloorEdgeBand{dir, Pose2{o.x(), o.y(), WrapPi(axis_yaw_odom_ + (side == 0 ? 0.5 : -0.5) * kPi)},
                            line + opt_.branch_line_tolerance_m, line + opt_.branch_line_band_m,
                            side == 0 ? -a1 : a0, side == 0 ? -a0 : a1};
        };
        record(k, gap_side_dir_, line_at[k]);
        if (crossing) {
          gap_other_dir_ = (dir_ + (k == 0 ? 3 : 1)) & 3;
          record(1 - k, gap_other_dir_, line_at[1 - k]);
        }
      }
      return true;
    }
  }
  return false;
}

bool Explorer::OnOpening(const Percept& p, int side, double width_m) {
  const int side_dir = (dir_ + (side == 0 ? 1 : 3)) & 3;
  const Eigen::Vector2d pos = map_pose_.Translation();
  const char* side_name = side == 0 ? "left" : "right";
  // Only where the corridor goes on: a corner (the end wall ahead) is left to the end detection.
  const double ahead_free = Free(p, axis_yaw_odom_, opt_.lookahead_m + 1.0, /*judging=*/true);
  if (ahead_free < opt_.sonar_end_gap_m) return false;
  const int known = map_.NodeNear(pos);
  if (known >= 0 && known == map_.DepartedFrom()) return false;  // still leaving that junction
  const bool known_side = known >= 0 && map_.Nodes()[known].branch[side_dir] != Branch::kUnknown;
  if (known_side && (map_.Nodes()[known].position_m - pos).norm() > opt_.branch_known_radius_m) {
    // Far from the node's position (e.g. an opening seen while leaving a side branch at an
    // angle) it is left alone: the end detection or the next opening takes over. With
    // opening_beside_wall_node, where the node's side was judged a wall, it is another opening
    // (the node a false stop beside it) and is looked at as a new one.
    if (!opt_.opening_beside_wall_node || map_.Nodes()[known].branch[side_dir] != Branch::kWall) return false;
  } else if (known_side) {
    // A junction met before whose side branch is known: pass unless the map routes into it.
    ++junctions_;
    node_ = map_.Arrive(pos, dir_, CameAlong());
    if (map_.Nodes()[node_].branch[dir_] == Branch::kUnknown) map_.SetBranch(node_, dir_, Branch::kOpen);
    const int next = map_.ChooseBranch(node_, dir_);
    if (next == dir_ || next < 0) {
      map_.Depart(node_, dir_);
      Emit(ExploreEvent::Kind::kJunction, p, 0,
           Format("passed junction %d (%s branch %s)", node_, side_name, BranchName(map_.Nodes()[node_].branch[side_dir])));
      return false;
    }
    Emit(ExploreEvent::Kind::kJunction, p, 0, Format("stopped at junction %d: the map routes elsewhere", node_));
    StartProbe();
    return true;
  }
  ++junctions_;
  node_ = map_.Arrive(pos, dir_, CameAlong());
  if (map_.Nodes()[node_].branch[dir_] == Branch::kUnknown) map_.SetBranch(node_, dir_, Branch::kOpen);
  Emit(ExploreEvent::Kind::kJunction, p, 0,
       Format("opening on the %s, %.1f m wide; ahead free %.1f m", side_name, width_m, ahead_free));
  StartProbe();
  gap_side_dir_ = side_dir;
  return true;
}

void Explorer::StartProbe(bool at_end) {
  probe_at_end_ = at_end;
  // A dead end judged on an earlier visit: look at its sides again (at most
  // reprobe_dead_end_visits times per node).
  if (node_ >= 0) {
    if (dead_end_reprobes_.size() <= static_cast<std::size_t>(node_)) dead_end_reprobes_.resize(static_cast<std::size_t>(node_) + 1, 0);
    const TopoNode& node = map_.Nodes()[static_cast<std::size_t>(node_)];
    const int left = (dir_ + 1) & 3, right = (dir_ + 3) & 3;
    if (node.branch[left] == Branch::kWall && node.branch[right] == Branch::kWall &&
        dead_end_reprobes_[static_cast<std::size_t>(node_)] < opt_.reprobe_dead_end_visits) {
      ++dead_end_reprobes_[static_cast<std::size_t>(node_)];
      map_.SetBranch(node_, left, Branch::kUnknown);
      map_.SetBranch(node_, right, Branch::kUnknown);
    }
  }
  last_ref_entropy_ = ReferenceEntropy();
  side_free_m_[0] = side_free_m_[1] = -1.0;
  gap_side_dir_ = gap_other_dir_ = -1;
  floor_edge_band_.reset();
  floor_edge_candidates_[0].reset();
  floor_edge_candidates_[1].reset();
  state_ = ExploreState::kProbe;
  probe_phase_ = 0;
  look_count_ = 0;
  look_sum_ = 0.0;
  n_probes_ = 0;
  // Before turning by odometry from the axis: the walls the memory holds outvote a drifted axis.
  double wall_axis = 0.0;
  if (WallAxis(&wall_axis)) {
    const double diff = std::remainder(wall_axis - axis_yaw_odom_, kPi / 2);
    if (std::abs(diff) > DegToRad(10.0)) RotateAxis(diff);
  }
  rot_ = Rotation{axis_yaw_odom_, 0};
}

// --- Back off -------------------------------------------------------------------------------

bool Explorer::FeelContact(const Percept& p, const Pose2& moved) {
  if (!opt_.feel_contacts) return false;
  // The way just driven: forward along a path straight enough to retrace by reversing straight
  // (curvature under kRetraceCurvature: 1 cm off the path over 0.1 m); turning in place or
  // reversing starts it afresh, standing still keeps it.
  constexpr double kRetraceCurvature = 2.0;  // rad/m
  if (moved.x > 1e-4 && std::abs(moved.yaw) <= kRetraceCurvature * moved.x) {
    forward_run_m_ += moved.x;
  } else if (moved.x < -1e-4 || std::abs(moved.yaw) > 1e-3) {
    forward_run_m_ = 0.0;
  }
  const double dt = p.stamp_s - last_cmd_s_;
  const bool pushing = last_cmd_s_ >= 0.0 && dt > 0.0 && last_cmd_.v_mps >= opt_.contact_min_v_mps &&
                       moved.x < opt_.contact_max_progress * last_cmd_.v_mps * dt;
  contact_run_ = pushing ? contact_run_ + 1 : 0;
  if (contact_run_ < opt_.contact_frames) return false;
  contact_run_ = 0;
  ++contacts_felt_;
  const Eigen::Vector2d d(std::cos(p.odom_T_robot.yaw), std::sin(p.odom_T_robot.yaw));
  memory_.InsertConfirmed(p.odom_T_robot.Translation() + (opt_.robot_radius_m + opt_.contact_point_gap_m) * d,
                          p.stamp_s);
  memory_.Gather(p.odom_T_robot, p.stamp_s);
  const double reverse_m = std::min(opt_.contact_reverse_m, forward_run_m_);
  Emit(ExploreEvent::Kind::kStall, p, 0,
       Format("contact felt: commanded %.2f m/s, no wheel progress; reversing %.2f m", last_cmd_.v_mps, reverse_m));
  stalled_since_start_ = true;
  state_ = ExploreState::kBackOff;
  backoff_from_ = p.odom_T_robot.Translation();
  backoff_reverse_m_ = reverse_m;
  backoff_until_s_ = p.stamp_s + 2.0 * reverse_m / kReverseMps;  // a time limit as well
  forward_run_m_ = 0.0;
  stall_.Reset();
  return true;
}

Command Explorer::BackOffStep(const Percept& p) {
  if (backoff_reverse_m_ >= 0.0) {
    // After a contact: reverse the measured distance along the way just driven.
    if (p.stamp_s < backoff_until_s_ && (p.odom_T_robot.Translation() - backoff_from_).norm() < backoff_reverse_m_ - 0.005)
      return {-kReverseMps, 0.0};
    backoff_reverse_m_ = -1.0;
  } else if (p.stamp_s < backoff_until_s_) {
    return {-kReverseMps, 0.0};
  }
  // Treat the blockage like the end of the corridor: look and choose. Blocked right after setting
  // off (the node's position or the branch was wrong): that branch is a wall after all.
  ++ends_;
  last_ref_entropy_ = ReferenceEntropy();
  const bool at_departure = sonar_seen_ && node_ >= 0 && travel_in_corridor_m_ < 0.5 * opt_.map.merge_radius_m;
  if (at_departure) {
    map_.CancelDeparture();  // still at the node it set off from
  } else {
    node_ = map_.Arrive(map_pose_.Translation(), dir_, CameAlong());
  }
  map_.SetBranch(node_, dir_, Branch::kWall, at_departure);
  StartProbe();
  return {};
}

// --- Probe: look left and right, decide by entropy --------------------------------------------

Command Explorer::ProbeStep(const Percept& p) {
  const TopoNode& node = map_.Nodes()[node_];
  while (probe_phase_ < 2 && node.branch[(dir_ + probe_sides_[probe_phase_]) & 3] != Branch::kUnknown) {
    ++probe_phase_;  // already known from an earlier visit: no need to look again
    rot_.settle = 0;
  }
  if (probe_phase_ >= 2) {
    Decide(p);
    return {};
  }
  const int side_dir = (dir_ + probe_sides_[probe_phase_]) & 3;
  rot_.target_yaw = WrapPi(axis_yaw_odom_ + probe_sides_[probe_phase_] * kPi / 2.0);
  Command cmd;
  if (look_count_ == 0 && !Rotate(p, rot_, cmd)) return cmd;
  if (p.glance_entropy_nats) {
    look_sum_ += *p.glance_entropy_nats;
    ++look_count_;
  }
  if (look_count_ < opt_.look_frames) return {};
  // With the sonar, wait for a scan taken facing this side and judge by free travel.
  if (sonar_seen_ && p.sonar == nullptr) return {};
  const double h = look_sum_ / look_count_;
  side_entropy_[probe_phase_] = h;
  side_free_m_[probe_phase_] = sonar_seen_ ? Free(p, rot_.target_yaw, opt_.lookahead_m + 1.0, /*judging=*/true) : -1.0;
  // With the sonar, a side is open when free for sonar_open_free_m; the side where the sonar
  // memory showed an opening while following is also open when the entropy rule says so (from
  // the mouth of a branch the sonar's blind range often holds a wall corner).
  const bool open_by_entropy = h >= opt_.open_entropy_ratio * last_ref_entropy_;
  const bool brick_facing = opt_.probe_max_wall_lines > 0.0 && p.sonar_wall_lines >= opt_.probe_max_wall_lines;
  const bool open_by_sonar = side_free_m_[probe_phase_] >= opt_.sonar_open_free_m &&
                             h >= opt_.sonar_open_min_entropy_ratio * last_ref_entropy_ &&
                             !(opt_.blind_side_needs_lines && last_scan_blind_) && !brick_facing;
  // At the end of a corridor, the latest scan's blocked-near columns facing this side may be the
  // near wall of a branch whose mouth the robot stands off-centre in (an L corner reached along
  // its end wall): with end_probe_memory, a side the entropy rule calls open is open where the
  // remembered points alone leave it free, unless the scan facing it shows a brick wall's lines
  // (probe_wall_lines_memory: such a wall inside the blind range leaves no point to remember).
  const bool open_by_memory = opt_.end_probe_memory && probe_at_end_ && sonar_seen_ && open_by_entropy &&
                              !(opt_.probe_wall_lines_memory && brick_facing) &&
                              memory_.FreeTravel(p.odom_T_robot, rot_.target_yaw, opt_.robot_radius_m + opt_.safety_margin_m,
                                                 opt_.lookahead_m + 1.0, false, true, 0.0, 0.0, /*kept_edges=*/false) >=
                                  opt_.sonar_open_free_m;
  // Where the floor has the walls' grey: the walls' lines show the side's corridor free.
  const bool open_by_lines = sonar_seen_ && WallLinesFree(p, rot_.target_yaw) &&
                             h >= opt_.sonar_open_min_entropy_ratio * last_ref_entropy_;
  const bool open = sonar_seen_ ? open_by_sonar || open_by_memory || open_by_lines ||
                                      ((side_dir == gap_side_dir_ || side_dir == gap_other_dir_) && open_by_entropy)
                                : open_by_entropy;
  map_.SetBranch(node_, side_dir, open ? Branch::kOpen : Branch::kWall);
  ++n_probes_;
  ++probe_phase_;
  look_count_ = 0;
  look_sum_ = 0.0;
  rot_.settle = 0;
  return {};
}

void Explorer::Decide(const Percept& p) {
  const TopoNode& node = map_.Nodes()[node_];
  int next = map_.ChooseBranch(node_, dir_);
  if (next < 0 && sonar_seen_) {
    // Nothing passable here: the corridor frame is probably lost (a wrong axis makes every
    // direction look blocked). Look all around again: a full turn re-acquires the axis from the
    // fused headings and picks the freest of its four directions.
    map_.CancelDeparture();
    ++turns_;
    Emit(ExploreEvent::Kind::kTurn, p, 0, "no passable branch: full turn to re-acquire the corridor");
    rescan_ = true;
    StartScan(p);
    return;
  }
  if (next < 0) next = Opposite(dir_);
  const int rel = (next - dir_ + 4) & 3;
  const int turn_deg = rel == 0 ? 0 : rel == 1 ? 90 : rel == 3 ? -90 : 180;
  const std::string note = Format("left %s, right %s, ahead %s (H %.2f/%.2f, ref %.2f, sonar free %.1f/%.1f m)",
                                  BranchName(node.branch[(dir_ + 1) & 3]), BranchName(node.branch[(dir_ + 3) & 3]),
                                  BranchName(node.branch[dir_]), side_entropy_[0], side_entropy_[1], last_ref_entropy_,
                                  side_free_m_[0], side_free_m_[1]);
  StartTurnTo(p, next, turn_deg, note);
}

void Explorer::StartTurnTo(const Percept& p, int dir, int turn_deg, const std::string& note) {
  turn_to_dir_ = dir;
  setting_off_ = false;
  const int rel = (dir - dir_ + 4) & 3;
  rot_ = Rotation{WrapPi(axis_yaw_odom_ + rel * kPi / 2.0), 0};
  state_ = ExploreState::kTurn;
  shift_m_ = 0.0;
  if (rel == 0) {  // straight on past a junction: not a turn
    Emit(ExploreEvent::Kind::kJunction, p, 0, "straight on: " + note);
    return;
  }
  ++turns_;
  double along = 0.0;
  if (opt_.mouth_centre_min_m > 0.0 && (rel == 1 || rel == 3) && MouthCentre(p, rel == 1 ? 0 : 1, &along) &&
      std::abs(along) >= opt_.mouth_centre_min_m && along >= -opt_.mouth_back_max_m) {
    shift_m_ = along;
    shift_from_ = p.odom_T_robot.Translation();
    shift_rot_ = Rotation{axis_yaw_odom_, 0};
    shift_aligned_ = false;
    shift_start_s_ = p.stamp_s;
    shift_progress_.Reset();
    Emit(ExploreEvent::Kind::kTurn, p, turn_deg, note + Format("; to the mouth's centre first: %+.2f m along", along));
    return;
  }
  Emit(ExploreEvent::Kind::kTurn, p, turn_deg, note);
}

bool Explorer::MouthCentre(const Percept& p, int side, double* along_m) const {
  double wall_m = last_wall_m_[side];
  if (!(wall_m > 0.0)) return false;
  // The wall line where it stands now: moved by the robot's sideways travel since it was read.
  if (opt_.mouth_wall_line) {
    const Eigen::Vector2d outward = side == 0 ? AxisLeft() : Eigen::Vector2d(-AxisLeft());
    wall_m -= outward.dot(p.odom_T_robot.Translation() - last_wall_at_[side]);
    if (!(wall_m > 0.0)) return false;
  }
  // Where along the axis the remembered points lie inside the branch (beyond the corridor's wall
  // line on that side): the branch's near and far walls; with mouth_wall_line also the corridor's
  // own wall on that side, which bounds the mouth where it still stands. Farther than the memory's query radius
  // too: the near wall of a branch wider than the corridor was seen from the corridor only far off.
  const double reach = opt_.mouth_centre_max_m + 0.5 * opt_.branch_max_width_m;
  const double l0 = opt_.mouth_wall_line ? std::max(0.0, wall_m - 0.2) : wall_m + 0.25;
  const double l1 = wall_m + opt_.mouth_band_m;
  std::vector<Eigen::Vector2d> points;
  memory_.PointsInRect(Pose2{p.odom_T_robot.x, p.odom_T_robot.y, axis_yaw_odom_}, -reach, reach, side == 0 ? l0 : -l1,
                       side == 0 ? l1 : -l0, p.stamp_s, &points);
  std::vector<double> along;
  along.reserve(points.size());
  for (const Eigen::Vector2d& q : points) along.push_back(q.x());
  // The near corner also where this side's last wall run ended (as TrackSides takes it): from the
  // corridor the near wall of a branch wider than the corridor is seen only from far off, if at all.
  const SideTrack& tr = sides_[side];
  if (tr.wall_first_m >= 0.0) along.insert(along.end(), 2, WallRunEndAlong(side));
  const std::optional<double> centre = MouthGapCentre(std::move(along), opt_);
  if (!centre) return false;
  *along_m = *centre;
  return true;
}

std::optional<double> MouthGapCentre(std::vector<double> along, const ExplorerOptions& options) {
  std::sort(along.begin(), along.end());
  constexpr double kCluster = 0.3;
  if (options.mouth_drop_strays) {
    // A point with no other within kCluster is no wall: it must not split a mouth in two.
    std::vector<double> kept;
    kept.reserve(along.size());
    for (std::size_t i = 0; i < along.size(); ++i)
      if ((i > 0 && along[i] - along[i - 1] <= kCluster) || (i + 1 < along.size() && along[i + 1] - along[i] <= kCluster))
        kept.push_back(along[i]);
    along.swap(kept);
  }
  bool found = false;
  double best = 0.0;
  for (std::size_t i = 1; i + 2 < along.size(); ++i) {
    const double width = along[i + 1] - along[i];
    if (width < options.branch_min_width_m || width > options.branch_max_width_m) continue;
    // Each side of the gap a wall (two points at least), not one stray point.
    if (along[i] - along[i - 1] > kCluster || along[i + 2] - along[i + 1] > kCluster) continue;
    const double centre = 0.5 * (along[i] + along[i + 1]);
    if (!found || std::abs(centre) < std::abs(best)) best = centre;
    found = true;
  }
  if (!found || std::abs(best) > options.mouth_centre_max_m) return std::nullopt;
  return best;
}

Command Explorer::ShiftStep(const Percept& p) {
  Command cmd;
  if (!shift_aligned_) {
    if (!Rotate(p, shift_rot_, cmd)) return cmd;
    shift_aligned_ = true;
  }
  // Held up where the sonar sees nothing (a wall too near for the floor in front of it to be
  // seen): the wheels stop moving while the guard lets the robot drive. Turn from here. (Where
  // the guard stops it, the drive's time limit applies.)
  if (opt_.shift_stall_s > 0.0) {
    constexpr double kDrivingMps = 0.05;  // a command at least this fast counts as driving
    if (last_cmd_s_ < 0.0 || std::abs(last_cmd_.v_mps) < kDrivingMps) {
      shift_progress_.Reset();
    } else if (shift_progress_.Stalled(p.stamp_s, p.odom_T_robot.Translation(), opt_.shift_stall_s,
                                       0.2 * kDrivingMps * opt_.shift_stall_s, last_cmd_s_)) {
      Emit(ExploreEvent::Kind::kStall, p, 0, "no wheel progress toward the mouth's centre: turning from here");
      shift_m_ = 0.0;
      return {};
    }
  }
  const Eigen::Vector2d d(std::cos(shift_rot_.target_yaw), std::sin(shift_rot_.target_yaw));
  const double remaining = shift_m_ - (p.odom_T_robot.Translation() - shift_from_).dot(d);
  // Done, or held up (the sonar guard found the way along the axis blocked): turn from here.
  const double limit_s = 4.0 + 3.0 * std::abs(shift_m_) / opt_.mouth_speed_mps;
  if (std::abs(remaining) < 0.03 || remaining * shift_m_ < 0.0 || p.stamp_s - shift_start_s_ > limit_s) {
    shift_m_ = 0.0;
    return {};
  }
  cmd.v_mps = std::copysign(std::clamp(std::abs(remaining), 0.08, opt_.mouth_speed_mps), remaining);
  cmd.omega_rps = std::clamp(opt_.heading_gain * WrapPi(shift_rot_.target_yaw - p.odom_T_robot.yaw), -opt_.max_omega_rps,
                             opt_.max_omega_rps);
  return cmd;
}

Command Explorer::TurnStep(const Percept& p) {
  Command cmd;
  if (shift_m_ != 0.0) return ShiftStep(p);
  if (!Rotate(p, rot_, cmd)) return cmd;
  axis_yaw_odom_ = rot_.target_yaw;
  dir_ = turn_to_dir_;
  map_yaw_offset_ = WrapPi(axis_yaw_odom_ - YawOfDirection(dir_));
  map_.Depart(node_, dir_);
  std::optional<FloorEdgeBand> into_band;
  for (std::optional<FloorEdgeBand>& b : floor_edge_candidates_) {
    if (b && b->dir == dir_) into_band = b;
    b.reset();
  }
  StartFollow(p);
  if (into_band) {
    // Into an opening found past a floor edge: until the robot has crossed that band, what the
    // memory holds there (seen again from the mouth, nearer than any second step) is floor.
    floor_edge_band_ = into_band;
    ClearFloorEdgeBand(p);
  }
  return {};
}

}  // namespace squint::explore
