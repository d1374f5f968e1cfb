// `squint explore`: autonomous exploration of a simulated building in closed loop (the README's
// main job), and `squint eval explore`: seeded starts per world, a table and one map per world.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <algorithm>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "command.hpp"
#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/config/corridor_yaml.hpp"
#include "squint/eval/explore_compare.hpp"
#include "squint/eval/explore_run.hpp"
#include "squint/eval/plot.hpp"
#include "squint/io/atomic_output.hpp"
#include "squint/explore/visual_sonar.hpp"
#include "squint/sim/renderer.hpp"
#include "squint/sim/world.hpp"

namespace squint::app {
namespace {

// The explorer's switchable behaviours, the same flags on `explore` and `eval explore`. Each is
// on by default since session 12 except --light-heading (docs/explore.md); `--no-X` turns one
// off, and `--X` (the session 10/11 spelling, when they were off by default) is still accepted.
struct ExplorerVariants {
  // The explorer's axis follows the Perceiver's heading filter, which the runner then runs beside
  // the per-frame fusion (ExplorerOptions::filtered_axis_gain).
  bool heading_filter = true;
  // With the filter, a new corridor's filter starts from the explorer's axis with this standard
  // deviation (ExplorerOptions::heading_filter_prior_std_deg; 0: no prior).
  double heading_prior_std_deg = 3.0;
  // Side openings are found past a floor-material edge read beyond the wall line
  // (ExplorerOptions::branch_line_tolerance_m).
  bool floor_edge_openings = true;
  // Centre on the ceiling lights' line in the glance (ExplorerOptions::light_centre_gain).
  bool light_centring = true;
  // Move to a side branch's centre line before turning into it (ExplorerOptions::mouth_centre_min_m).
  bool mouth_centring = true;
  // A side free by the sonar needs a look whose entropy is not a wall's
  // (ExplorerOptions::sonar_open_min_entropy_ratio).
  bool sonar_open_entropy = true;
  // The lights' line's heading also moves the corridor axis (ExplorerOptions::light_axis_gain; off).
  bool light_heading = false;
  // The drift of the offsets from the lights' line turns the axis (ExplorerOptions::light_drift_gain; 0: off).
  double light_drift_gain = 0.0;
  // The obstacle pipeline in the loop (eval::ExploreRunOptions::obstacle_pipeline; off).
  bool obstacle_pipeline = false;
  // A sonar column clears the memory only up to its own reading, so the median across columns
  // does not erase a thin thing such as a chair leg (ObstacleMemoryOptions::clear_own_within_m; off).
  bool own_range_clearing = false;
  // ...in the form that keeps what it does not clear for driving only, the judgements of walls and
  // openings clearing as without it (ObstacleMemoryOptions::clear_own_driving_only; on since session 49).
  bool own_range_driving = true;
  // The walls' base lines from the floor's texture steer the corridor axis
  // (ExplorerOptions::wall_line_axis_gain; on since session 17).
  bool wall_lines = true;
  // At the end of a corridor a side open by entropy is open where the remembered points leave it
  // free, whatever the latest scan's blocked-near columns say (ExplorerOptions::end_probe_memory; on since session 17).
  bool end_probe_memory = true;
  // With the walls' lines: where they show the corridor free this far, a sonar end is not taken
  // and a probed side is open (ExplorerOptions::wall_line_free_m; 0: off; 2.5 since session 17).
  double wall_line_free_m = 2.5;
  // A break in a side wall handled as an opening starts a new wall run (ExplorerOptions::rearm_after_gap; on since session 17).
  bool rearm_after_gap = true;
  // The walls' lines' frame binned from one twice its size (ExploreRunOptions::wall_lines_binned; on since session 17).
  bool wall_lines_binned = true;
  // A one-row best line is left out and the lines sought again (WallLineOptions::drop_one_row_line; off).
  bool wall_lines_drop_row = false;
  // Mouth centring bounded by the corridor's own wall line as it stands now (ExplorerOptions::mouth_wall_line; on since session 17).
  bool mouth_wall_line = true;
  // Mouth centring leaves out stray points that would split a mouth (ExplorerOptions::mouth_drop_strays).
  bool mouth_drop_strays = true;
  // The walls' lines also set the axis in the start-up scan and alignment (ExplorerOptions::wall_line_align; off).
  bool wall_line_align = false;
  // ...only where they disagree with the glance by more than this (degrees; ExplorerOptions::wall_line_align_over_deg; 0: off; 25 since session 45).
  double wall_line_align_over_deg = 25.0;
  // A scan takes no direction free to its reach whose entropy is below this fraction of the best of the four (ExplorerOptions::scan_entropy_floor; 0: off; 0.9 since session 45).
  double scan_entropy_floor = 0.9;
  // A scan takes no direction with a wall's entropy (below this fraction of the best; ExplorerOptions::scan_wall_entropy; 0: off; 0.7 since session 49).
  double scan_wall_entropy = 0.7;
  // Keep off a wall the lines show nearer than this (metres; ExplorerOptions::wall_keep_m; 0: off; 0.45 since session 49).
  double wall_keep_m = 0.45;
  // ...leaving out lines nearer than this (metres; ExplorerOptions::wall_keep_min_m; 0: none; 0.25 since session 49).
  double wall_keep_min_m = 0.25;
  // An opening beside a junction whose side was judged a wall is looked at (ExplorerOptions::opening_beside_wall_node; off).
  bool opening_beside_wall_node = false;
  // The branch a stop's node was entered by is explored only when the robot came along it
  // (ExplorerOptions::arrival_min_travel_m; 0: always; 1.0 since session 18).
  double arrival_min_travel_m = 1.0;
  // The drive to a mouth's centre ends when the wheels make no progress for this long
  // (ExplorerOptions::shift_stall_s; 0: off; 0.3 since session 18).
  double shift_stall_s = 0.3;
  // A probed side whose view is blind to the sonar is open only by the walls' lines (and the
  // other non-sonar rules) (ExplorerOptions::blind_side_needs_lines; on since session 18).
  bool blind_side_lines = true;
  // In a blind view, sonar columns whose bottom the walls' lines' frame shows smooth stay
  // blocked near (ExplorerOptions::blind_texture_ratio; 0: off; 0.35 since session 18).
  double blind_texture_ratio = 0.35;
  // The start's look scans all around where the sonar's view is blind (ExplorerOptions::scan_blind_start; on since session 18).
  bool scan_blind_start = true;
  // With --blind-texture, also the sonar's own unknown columns (ExplorerOptions::blind_texture_unknown; off).
  bool blind_texture_unknown = false;
  // --blind-texture-unknown's rule until the robot has driven this far since its start
  // (ExplorerOptions::blind_texture_start_m; 0: off; 2.0 since session 19).
  double blind_texture_start_m = 2.0;
  // A scan's view with a brick wall's lines across this fraction of the sonar's bands is a wall
  // view (ExplorerOptions::scan_wall_lines; 0: off; 0.75 since session 19).
  double scan_wall_lines = 0.75;
  // A blind view near (travel, yaw, time) the last wall view is a wall (ExplorerOptions::wall_view_hold_m;
  // 0: off, the default: it costs `default`'s middle corridor; docs/explore.md, session 19).
  double wall_view_hold_m = 0.0;
  // The drive to a mouth's centre trusts the floor seen on the way in (ExplorerOptions::shift_trusts_memory;
  // on since session 19).
  bool shift_trusts_memory = true;
  // ...and takes the remembered points' free travel where they leave less than this (metres;
  // ExplorerOptions::shift_points_within_m; 0: off; 1.2 since session 45).
  double shift_points_within_m = 1.2;
  // Brick lines count for this long (ExplorerOptions::wall_lines_hold_s; 0: the latest frame; 1.0 since session 19).
  double wall_lines_hold_s = 1.0;
  // A side whose probe scan shows brick lines in this fraction of its bands is not open by the sonar (ExplorerOptions::probe_max_wall_lines; 0.375 since session 25).
  double probe_max_wall_lines = 0.375;
  // ...nor, at a corridor's end, open by the remembered points (ExplorerOptions::probe_wall_lines_memory; on since session 31).
  bool probe_wall_lines_memory = true;
  // An end the sonar reads this close makes the branch ahead a wall whatever the map says
  // (ExplorerOptions::sonar_end_blocks_m; 0: off; 1.0 since session 18).
  double sonar_end_blocks_m = 1.0;
  // Creep toward a place the map holds as a dead end from this far (ExplorerOptions::known_end_slow_m; 0: off).
  double known_end_slow_m = 0.0;
  // ...only while the fused distance reads the end this much farther than the map (ExplorerOptions::known_end_disagree_m; 0: always).
  double known_end_disagree_m = 0.0;
  // A far column whose bottom differs this much from the floor is blocked near (explore::VisualSonarOptions::far_floor_max_diff; 0: off; 40 since session 26).
  double far_floor_diff = 40.0;
  // ...and a step in range this far or farther too (explore::VisualSonarOptions::far_floor_from_m; 0: far only; 2 since session 36).
  double far_floor_from_m = 2.0;
  // The floor reference from boundary columns first (explore::VisualSonarOptions::floor_ref_boundaries; off).
  bool floor_ref_boundaries = false;
  // A view smooth all over does not become the floor's texture reference (ExplorerOptions::blind_texture_keep_ref;
  // on since session 20).
  bool blind_texture_keep_ref = true;
  // ...judged against the largest reference of the hold (ExplorerOptions::blind_texture_keep_peak;
  // on since session 22).
  bool blind_texture_keep_peak = true;
  // The blocked-near sonar columns of the last S seconds limit the free travel, not the latest
  // scan's alone (ObstacleMemoryOptions::blocked_hold_s; 0: off; 0.5 since session 21).
  double blocked_hold_s = 0.5;
  // ...their columns only while the latest scan still looks along them
  // (ObstacleMemoryOptions::blocked_hold_in_view; on since session 23).
  bool blocked_hold_in_view = true;
  // A blocked-near column's thing is assumed as near as this for its sector (ObstacleMemoryOptions::blocked_min_range_m; 0.6).
  double blocked_min_range_m = 0.6;
  // ...and this far once following has come 1.6 m along a corridor (ExplorerOptions::settled_blocked_min_range_m; 0: off, the default).
  double settled_blocked_min_range_m = 0.0;
  // ...and this far from a start or scan until 1.6 m of following or a turn (ExplorerOptions::setoff_blocked_min_range_m; 0: off; 0.45 since session 28).
  double setoff_blocked_min_range_m = 0.45;
  // ...and the vertical edges ranged by the travel's parallax (ExplorerOptions::setoff_near_edges; on since session 32).
  bool setoff_near_edges = true;
  // ...and the held near edges out of the view where the robot still stands (ExplorerOptions::setoff_standing_hold_m; 0: off, the default).
  double setoff_standing_hold_m = 0.0;
  // Watch for the robot's own reflection and remember a wall on the mirror (ExplorerOptions::mirror_watch; on since session 29).
  bool mirror_watch = true;
  // A driven corridor closed by a stall right after setting off is reopened on the next arrival (TopoMapOptions::reopen_blocked_driven).
  bool reopen_blocked_driven = false;
  // The wall line's samples at least this far apart in travel (ExplorerOptions::branch_line_spacing_m; 0: one per step, the default).
  double branch_line_spacing_m = 0.0;
  // Feel contacts from the wheels, remember them and reverse the way just driven (ExplorerOptions::feel_contacts; on since session 30).
  bool feel_contacts = true;
  int contact_frames = 2;  // ...on this many steps in a row (ExplorerOptions::contact_frames)
  // Soft points along a blocked-near column's ray from this range on (ObstacleMemoryOptions::blind_points_from_m; 0: off; 0.6).
  double blind_points_from_m = 0.6;
  double blind_points_keep_s = 5.0;  // ...forgotten after this long (ObstacleMemoryOptions::blind_points_keep_s)
  // ...those of a near thing's edge after this long (ObstacleMemoryOptions::blind_points_edge_keep_s; 0: as the others).
  double blind_points_edge_keep_s = 15.0;
  // ...and serve driving only (ObstacleMemoryOptions::blind_points_edge_keep_driving_only).
  bool blind_points_edge_keep_driving_only = true;
  // A side wall abeam needs another point within this distance (ExplorerOptions::side_wall_cluster_m; 0: nearest point).
  double side_wall_cluster_m = 0.15;
  // The floor-edge band cleared only across the opening's span (ExplorerOptions::floor_edge_band_mouth).
  bool floor_edge_band_mouth = true;
  // Forward travel stops where the disc moved this far would cover a never-known-free cell beside
  // its path (ExplorerOptions::guard_unknown_step_m; 0: off).
  double guard_unknown_step_m = 0.0;
  double guard_unknown_after_m = 0.0;  // ...once the wheels travelled this far since the start
  // An opening's far edge only at points on that side's wall line (ExplorerOptions::far_edge_on_line).
  bool far_edge_on_line = false;
  // Points beyond a side's wall line seen only from farther than this neither end nor block its
  // opening (ExplorerOptions::branch_coarse_from_m; 0: off).
  double branch_coarse_from_m = 0.0;

  void Apply(eval::ExploreRunOptions& ro) const {
    ro.explorer.filtered_axis_gain = heading_filter ? 0.2 : 0.0;
    ro.explorer.heading_filter_prior_std_deg = heading_prior_std_deg;
    ro.explorer.branch_line_tolerance_m = floor_edge_openings ? 0.12 : 0.0;
    ro.explorer.light_centre_gain = light_centring ? 0.35 : 0.0;
    ro.explorer.mouth_centre_min_m = mouth_centring ? 0.25 : 0.0;
    ro.explorer.sonar_open_min_entropy_ratio = sonar_open_entropy ? 0.7 : 0.0;
    ro.explorer.light_axis_gain = light_heading ? 0.05 : 0.0;
    ro.explorer.light_drift_gain = light_drift_gain;
    ro.obstacle_pipeline = obstacle_pipeline;
    ro.explorer.memory.clear_own_within_m =
        own_range_clearing || own_range_driving ? explore::ExplorerMemoryDefaults().clear_own_within_m : 0.0;
    ro.explorer.memory.clear_own_driving_only = own_range_driving && !own_range_clearing;
    ro.explorer.wall_line_axis_gain = wall_lines ? 0.2 : 0.0;
    ro.explorer.end_probe_memory = end_probe_memory;
    ro.explorer.wall_line_free_m = wall_line_free_m;
    ro.explorer.rearm_after_gap = rearm_after_gap;
    ro.wall_lines_binned = wall_lines_binned;
    ro.wall_lines.drop_one_row_line = wall_lines_drop_row;
    ro.explorer.mouth_wall_line = mouth_wall_line;
    ro.explorer.mouth_drop_strays = mouth_drop_strays;
    ro.explorer.wall_line_align = wall_line_align;
    ro.explorer.wall_line_align_over_deg = wall_line_align_over_deg;
    ro.explorer.scan_entropy_floor = scan_entropy_floor;
    ro.explorer.scan_wall_entropy = scan_wall_entropy;
    ro.explorer.wall_keep_m = wall_keep_m;
    ro.explorer.wall_keep_min_m = wall_keep_min_m;
    ro.explorer.opening_beside_wall_node = opening_beside_wall_node;
    ro.explorer.arrival_min_travel_m = arrival_min_travel_m;
    ro.explorer.shift_stall_s = shift_stall_s;
    ro.explorer.blind_side_needs_lines = blind_side_lines;
    ro.explorer.blind_texture_ratio = blind_texture_ratio;
    ro.explorer.scan_blind_start = scan_blind_start;
    ro.explorer.blind_texture_unknown = blind_texture_unknown;
    ro.explorer.blind_texture_start_m = blind_texture_start_m;
    ro.explorer.scan_wall_lines = scan_wall_lines;
    ro.explorer.wall_view_hold_m = wall_view_hold_m;
    ro.explorer.shift_trusts_memory = shift_trusts_memory;
    ro.explorer.shift_points_within_m = shift_points_within_m;
    ro.explorer.wall_lines_hold_s = wall_lines_hold_s;
    ro.explorer.probe_max_wall_lines = probe_max_wall_lines;
    ro.explorer.probe_wall_lines_memory = probe_wall_lines_memory;
    ro.explorer.sonar_end_blocks_m = sonar_end_blocks_m;
    ro.explorer.known_end_slow_m = known_end_slow_m;
    ro.explorer.known_end_disagree_m = known_end_disagree_m;
    ro.sonar.far_floor_max_diff = far_floor_diff;
    ro.sonar.far_floor_from_m = far_floor_from_m;
    ro.sonar.floor_ref_boundaries = floor_ref_boundaries;
    ro.explorer.blind_texture_keep_ref = blind_texture_keep_ref;
    ro.explorer.blind_texture_keep_peak = blind_texture_keep_peak;
    ro.explorer.memory.blocked_hold_s = blocked_hold_s;
    ro.explorer.memory.blocked_hold_in_view = blocked_hold_in_view;
    ro.explorer.memory.blocked_min_range_m = blocked_min_range_m;
    ro.explorer.settled_blocked_min_range_m = settled_blocked_min_range_m;
    ro.explorer.setoff_blocked_min_range_m = setoff_blocked_min_range_m;
    ro.explorer.setoff_near_edges = setoff_near_edges;
    ro.explorer.setoff_standing_hold_m = setoff_standing_hold_m;
    ro.explorer.mirror_watch = mirror_watch;
    ro.explorer.map.reopen_blocked_driven = reopen_blocked_driven;
    ro.explorer.branch_line_spacing_m = branch_line_spacing_m;
    ro.explorer.feel_contacts = feel_contacts;
    ro.explorer.contact_frames = contact_frames;
    ro.explorer.memory.blind_points_from_m = blind_points_from_m;
    ro.explorer.memory.blind_points_keep_s = blind_points_keep_s;
    ro.explorer.memory.blind_points_edge_keep_s = blind_points_edge_keep_s;
    ro.explorer.memory.blind_points_edge_keep_driving_only = blind_points_edge_keep_driving_only;
    ro.explorer.side_wall_cluster_m = side_wall_cluster_m;
    ro.explorer.floor_edge_band_mouth = floor_edge_band_mouth;
    ro.explorer.guard_unknown_step_m = guard_unknown_step_m;
    ro.explorer.guard_unknown_after_m = guard_unknown_after_m;
    ro.explorer.far_edge_on_line = far_edge_on_line;
    ro.explorer.branch_coarse_from_m = branch_coarse_from_m;
  }

  void AddFlags(CLI::App* cmd, bool as_explore) {
    auto text = [&](const char* full) -> std::string { return as_explore ? full : "As `squint explore`"; };
    cmd->add_flag("--heading-filter,!--no-heading-filter", heading_filter,
                  text("The corridor axis follows the Perceiver's heading filter over time (on by default; docs/explore.md, sessions 10 and 12)"));
    cmd->add_option("--heading-prior-std", heading_prior_std_deg,
                    text("With the heading filter: a new corridor's filter starts from the explorer's axis with this standard deviation, degrees (0: no prior)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 90.0));
    cmd->add_flag("--floor-edge-openings,!--no-floor-edge-openings", floor_edge_openings,
                  text("Find side openings past a floor edge read beyond the wall line (on by default; docs/explore.md, session 11)"));
    cmd->add_flag("--light-centring,!--no-light-centring", light_centring,
                  text("Centre on the ceiling lights' line in the glance where it is seen, else on the side walls (on by default; docs/explore.md, session 11)"));
    cmd->add_flag("--mouth-centring,!--no-mouth-centring", mouth_centring,
                  text("Move to a side branch's centre line, from its remembered walls, before turning into it (on by default; docs/explore.md, session 12)"));
    cmd->add_flag("--sonar-open-entropy,!--no-sonar-open-entropy", sonar_open_entropy,
                  text("A side free by the sonar is open only if its glance entropy is not a wall's, 0.7 of the corridor's (on by default; docs/explore.md, session 12)"));
    cmd->add_flag("--light-heading,!--no-light-heading", light_heading,
                  text("The ceiling lights' line's heading also steers the corridor axis (off by default; docs/explore.md, session 12)"));
    cmd->add_option("--light-drift-gain", light_drift_gain,
                    text("The drift of the offsets from the lights' line over the travel turns the corridor axis by this gain per frame (0: off; docs/explore.md, session 13)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_flag("--obstacle-pipeline,!--no-obstacle-pipeline", obstacle_pipeline,
                  text("Run the obstacle pipeline (inverse perspective, outlines, polar map, free-gap steering) on a 256x192 frame every 12th frame while following; its advice overrides the corridor following (off by default; docs/explore.md)"));
    cmd->add_flag("--own-range-clearing,!--no-own-range-clearing", own_range_clearing,
                  text("A visual-sonar column clears the obstacle memory only up to its own reading within 1.2 m (none where it was itself blocked near), so thin things such as chair legs stay remembered (off by default; docs/explore.md, session 14)"));
    cmd->add_flag("--own-range-driving,!--no-own-range-driving", own_range_driving,
                  text("Own-range clearing (--own-range-clearing, which takes precedence) for driving only: what a visual-sonar column's own reading within 1.2 m does not clear stays remembered for the disc's free travel only, while the judgements of walls, ends and openings clear it as without it, so a chair leg the median voted out still stops the robot but a carpet's blocked-near columns do not close a corridor (on by default since session 49; docs/explore.md, sessions 48 and 49)"));
    cmd->add_flag("--wall-lines,!--no-wall-lines", wall_lines,
                  text("The walls' base lines, where the floor's texture ends in a 128x96 frame every 3rd frame, steer the corridor axis while following; measured with --end-probe-memory (on by default since session 17; docs/explore.md, sessions 15 and 17)"));
    cmd->add_flag("--end-probe-memory,!--no-end-probe-memory", end_probe_memory,
                  text("At the end of a corridor a side open by the entropy rule is open where the remembered points leave it free, whatever the latest sonar scan's blocked-near columns say (on by default since session 17; docs/explore.md, sessions 15 and 17)"));
    cmd->add_flag("--wall-lines-binned,!--no-wall-lines-binned", wall_lines_binned,
                  text("With --wall-lines: their frame is the camera's image downsampled (rendered at twice the size, one sample and the sensor's noise per pixel, averaged over 2x2 blocks), so the noise averages; at the loop's noise most frames then read (on by default since session 17; docs/explore.md, sessions 16 and 17)"));
    cmd->add_flag("--wall-lines-drop-row,!--no-wall-lines-drop-row", wall_lines_drop_row,
                  text("With --wall-lines: a frame whose best line is one image row's points (a far foot across the view, an end wall's, which says nothing of the direction) leaves that line and its points out and seeks the lines again among the rest, so a near wall's base beside it still reads (off by default; docs/explore.md, session 46)"));
    cmd->add_option("--wall-line-free", wall_line_free_m,
                    text("With --wall-lines: where the walls' lines show a corridor free this far ahead (metres), an end read by the visual sonar alone is not taken and a probed side is open (0: off; 2.5 by default since session 17; docs/explore.md, sessions 16 and 17)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 8.0));
    cmd->add_flag("--mouth-wall-line,!--no-mouth-wall-line", mouth_wall_line,
                  text("Mouth centring takes the corridor's wall line where it stands now (moved by the robot's sideways travel since it was read) and its remembered points as bounds too, so a gap along which the wall still stands is no mouth (on by default; docs/explore.md, session 17)"));
    cmd->add_flag("--mouth-drop-strays,!--no-mouth-drop-strays", mouth_drop_strays,
                  text("Mouth centring leaves out a remembered point with no other within 0.3 m along the axis: one stray point inside a mouth split it into two gaps, neither with a wall on both sides, and the robot turned into corridor-8's cross corridor from 1 m off its centre line (on by default since session 39; docs/explore.md, sessions 37 and 39)"));
    cmd->add_flag("--wall-line-align,!--no-wall-line-align", wall_line_align,
                  text("With --wall-lines: their frames are also taken while scanning and aligning at a standstill, and their heading modulo 90 degrees sets the axis there (off by default; docs/explore.md, session 17)"));
    cmd->add_option("--wall-line-align-over", wall_line_align_over_deg,
                    text("With --wall-lines and without --wall-line-align: the walls' lines are read while scanning and aligning at a standstill too, and set the axis there only where they disagree with the glance by more than this many degrees; where they agree the run is the run without it (0) step for step (summary.json counts the overrides as align_line_overrides; 0: off; 25 by default since session 45; docs/explore.md, sessions 42 and 45)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 45.0));
    cmd->add_option("--wall-keep", wall_keep_m,
                    text("With --wall-lines: while setting off (from the start or a look around in place, for the first 1.6 m of following), a wall line read in the last 0.5 s within 15 degrees of the axis and nearer to the robot's centre than this (metres) bounds the heading to a few degrees away from the line's own direction, whatever the axis held says: near a wall the glance's heading is biased and the visual sonar may see no floor edge (summary.json counts the frames it bounded as wall_keep_frames; 0: off; 0.45 by default since session 49; docs/explore.md, sessions 46, 47 and 49)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 2.0));
    cmd->add_option("--scan-entropy-floor", scan_entropy_floor,
                    text("A scan in place does not set off along a direction of its axis that the memory finds free to the scan's full reach (nothing ranged there) when its glance entropy is below this fraction of the highest of the four: a door up close read as a corridor view and, its near columns forgotten, as the only free direction; a run whose scans never lose their choice to this is the run without it step for step (summary.json counts the scans it changed as scan_entropy_skips; 0: off; 0.9 by default since session 45; docs/explore.md, sessions 43 and 45)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--wall-keep-min", wall_keep_min_m,
                    text("With --wall-keep: a line nearer to the robot's centre than this (metres) is left out, as no wall can stand there while the robot touches nothing (a line on the floor read as a wall 0.18 m away turned the robot into a chair; 0: none left out; 0.25 by default since session 49; docs/explore.md, sessions 47 and 49)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 2.0));
    cmd->add_option("--scan-wall-entropy", scan_wall_entropy,
                    text("A scan in place does not set off along a direction of its axis whose glance entropy is below this fraction of the highest of the four, whatever the memory's free travel there, while another (not kept out by --scan-entropy-floor) is left: a brick wall 0.4 m away has a wall's entropy while its mortar courses range it metres off (summary.json counts the scans it changed as scan_wall_entropy_skips; 0: off; 0.7 by default since session 49; docs/explore.md, sessions 47 and 49)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_flag("--opening-beside-wall-node,!--no-opening-beside-wall-node", opening_beside_wall_node,
                  text("An opening found more than 0.8 m from a known junction whose side there was judged a wall is looked at as a new opening instead of being passed (off by default; docs/explore.md, session 17)"));
    cmd->add_option("--arrival-min-travel", arrival_min_travel_m,
                    text("A stop's node records the branch the robot came in by as explored only when it departed from a node or has driven this far (metres) since setting off: a robot that starts in a junction has not driven the corridor behind it (0: always; 1.0 by default since session 18; docs/explore.md, session 18)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 10.0));
    cmd->add_option("--shift-stall", shift_stall_s,
                    text("The drive to a side branch's mouth centre ends where the wheels make no progress for this long (seconds), a wall the sonar cannot see from up close, and the robot turns from there (0: only the drive's time limit; 0.3 by default since session 18; docs/explore.md, session 18)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 5.0));
    cmd->add_flag("--blind-side-lines,!--no-blind-side-lines", blind_side_lines,
                  text("Probing, a side whose sonar view is blind (nearly all columns blocked near, read as unknown because the glance looks like a corridor) is not open by the sonar's free travel, only by the walls' lines, the remembered points at an end or the entropy rule on an opening found while following: a door recess filling the view (on by default since session 18; docs/explore.md, session 18)"));
    cmd->add_option("--blind-texture", blind_texture_ratio,
                    text("With --wall-lines: in a view blind to the visual sonar (the floor and the walls of one grey) a column stays blocked near where the walls' lines' frame shows its bottom smoother than this fraction of the floor's texture: a wall within the camera's near blind range (0: off; 0.35 by default since session 18; docs/explore.md, session 18)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 0.99));
    cmd->add_flag("--blind-texture-unknown,!--no-blind-texture-unknown", blind_texture_unknown,
                  text("With --blind-texture: outside blind views too, a column the sonar reads unknown stays blocked near where its bottom is smooth, if every column the sonar shows floor in is textured at the bottom (off by default: corridor-2's seeded starts' coverage 0.82 -> 0.73; docs/explore.md, session 18)"));
    cmd->add_option("--blind-texture-start", blind_texture_start_m,
                    text("With --blind-texture: --blind-texture-unknown's rule applies until the robot has driven this far (metres) since its start, or until the robot first stalls: a start close to a wall of the floor's grey (0: off; 2.0 by default since session 19; docs/explore.md, session 19)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 100.0));
    cmd->add_option("--scan-wall-lines", scan_wall_lines,
                    text("Scanning in place, a view whose visual-sonar frame shows periodic horizontal lines (a brick wall's mortar) across at least this fraction of its bands counts as a wall filling the view, so the scan does not set off toward it (0: off; 0.75 by default since session 19; docs/explore.md, session 19)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--wall-view-hold", wall_view_hold_m,
                    text("A view blind to the visual sonar taken within this wheel travel (metres), 10 degrees of yaw and 1 s of the last view judged a wall filling the view is a wall too, so a glance entropy hovering at the threshold does not let the robot drive into a box up close (0: off, the default, since it cost `default`'s 45-minute runs its carpeted middle corridor on 8 of 32 seeds; docs/explore.md, session 19)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 10.0));
    cmd->add_flag("--shift-trusts-memory,!--no-shift-trusts-memory", shift_trusts_memory,
                  text("The drive forward to a side branch's mouth centre ignores blocked-near sonar columns where the floor was seen from farther back, as following does after 1.6 m, when the robot came that far along the corridor: a tiled floor's joints no longer hold it short of the centre (on by default since session 19; docs/explore.md, session 19)"));
    cmd->add_option("--shift-trusts-points", shift_points_within_m,
                    text("On the drive forward to a side branch's mouth centre (after 1.6 m along the corridor), where the remembered points leave less free travel than this many metres, that is the guard's free travel, not the latest scans' blocked-near columns: a wall filling the view at the end held the drive for its whole time limit although the robot ranged its base on the way in, and the robot turned off the branch's centre line (0: off; 1.2 by default since session 45; docs/explore.md, sessions 43 and 45)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 5.0));
    cmd->add_option("--wall-lines-hold", wall_lines_hold_s,
                    text("A brick wall's lines seen by the visual sonar within this many seconds keep the remembered floor from overruling its blocked-near columns, not the latest frame's alone (0: the latest frame; 1.0 by default since session 19; docs/explore.md, session 19)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 60.0));
    cmd->add_option("--probe-wall-lines", probe_max_wall_lines,
                    text("Probing, a side whose scan shows a brick wall's lines in at least this fraction of its bands is not open by the sonar's free travel (a brick wall inside the blind range reads as floor; 0: off; 0.375 by default since session 25; docs/explore.md, session 25)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_flag("--probe-wall-lines-memory,!--no-probe-wall-lines-memory", probe_wall_lines_memory,
                  text("At a corridor's end, a probed side whose scan shows those brick lines (--probe-wall-lines) is not open by the remembered points either: a brick wall inside the blind range leaves none (on by default since session 31; docs/explore.md, session 31)"));
    cmd->add_option("--sonar-end-blocks", sonar_end_blocks_m,
                    text("An end read by the visual sonar with less free travel ahead than this (metres) makes the branch ahead a wall even where the map holds it explored, so the robot does not go straight on into what it sees (0: off; 1.0 by default since session 18; docs/explore.md, session 18)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 3.0));
    cmd->add_option("--known-end-slow", known_end_slow_m,
                    text("Following toward a place the map holds as a dead end, creep (a quarter of cruise speed) from this far (metres) before where the robot stopped there last, a place whose branches ahead and to both sides are walls: a mirror end wall shows the corridor behind and the visual sonar reads floor running on (0: off, the default: it cost corridor-2's seeded starts coverage; docs/explore.md, session 20)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 20.0));
    cmd->add_option("--known-end-disagree", known_end_disagree_m,
                    text("With --known-end-slow: creep only while the fused distance to the corridor's end exceeds the map's distance to that dead end by more than this (metres): a mirror shows the corridor running on, a plain end wall reads where the map holds it (0: creep whatever the fused distance says)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 20.0));
    cmd->add_option("--far-floor-diff", far_floor_diff,
                    text("A visual-sonar column whose only step is at the horizon (floor all the way) but whose bottom rows differ from the frame's floor by more than this (grey levels) is blocked near: something taller than the camera stands within the blind range and fills it up to the horizon (0: off; 40 by default since session 26; docs/explore.md, session 26)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 255.0));
    cmd->add_option("--far-floor-from", far_floor_from_m,
                    text("With --far-floor-diff: a column whose step lies this far or farther (metres) is judged the same way, not only one whose step is at the horizon: the top edge of something standing within the blind range a little lower than the camera lies metres out on the floor (0: far steps only; 2 by default since session 36; docs/explore.md, sessions 34 and 36)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 20.0));
    cmd->add_flag("--floor-ref-boundaries,!--no-floor-ref-boundaries", floor_ref_boundaries,
                  text("The visual sonar's floor reference (the median bottom of its columns with a clear step, against which --far-floor-diff and the stepless columns are judged) comes from the columns whose step is a wall's or an obstacle's base in range, far columns joining only when those are too few: a box filling most of the view up close read far in every column and its own bottom became the reference (off by default; docs/explore.md, session 27)"));
    cmd->add_flag("--blind-texture-keep-ref,!--no-blind-texture-keep-ref", blind_texture_keep_ref,
                  text("With --blind-texture: a view whose bottom is smooth all over by the floor's recent texture (a plain door or wall filling the view up close, no floor below it) does not become the floor's texture reference, so its columns stay blocked near (on by default since session 20; docs/explore.md, session 20)"));
    cmd->add_flag("--blind-texture-keep-peak,!--no-blind-texture-keep-peak", blind_texture_keep_peak,
                  text("With --blind-texture-keep-ref: a view is smooth all over by the largest floor texture reference of the last 10 s, not the latest: turning toward a door up close walked the reference down to the door's own paint, one slightly smoother frame at a time (on by default since session 22; docs/explore.md, session 22)"));
    cmd->add_option("--blocked-hold", blocked_hold_s,
                    text("The visual sonar's blocked-near columns of the last S seconds (frames with at least 3 of them) limit the free travel where blocked columns count in full (the first 1.6 m of a corridor, off its axis, turning), each from where its frame was taken, not the latest frame's alone: a chair's thin legs flicker between blocked near and a boundary beyond the seat's shadow (0: off; 0.5 by default since session 21; docs/explore.md, session 21)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 10.0));
    cmd->add_flag("--blocked-hold-in-view,!--no-blocked-hold-in-view", blocked_hold_in_view,
                  text("With --blocked-hold: a held blocked-near column counts only while the latest frame still looks along it: a robot turning away from a wall it started close to was held by the wall's columns after they had left the view (on by default since session 23; off in session 22, when with it the main job met a wall after a false opening that --side-wall-cluster now removes; docs/explore.md, sessions 22 and 23)"));
    cmd->add_option("--blocked-min-range", blocked_min_range_m,
                    text("A visual-sonar column blocked near (something inside the camera's blind range, at an unknown distance) stops travel along the directions whose swept band would meet a thing this far along its ray (metres; 0.6 by default: ±36° for a 0.25 m disc with its 0.1 m margin, and the flank of the disc can meet a thing 0.36 m away; 0.45, ±51°, cleared every failing seeded start of seeds 1-32 but met a wall in a 45-minute run; docs/explore.md, session 27)"))
        ->capture_default_str()
        ->check(CLI::Range(0.05, 5.0));
    cmd->add_option("--settled-blocked-min-range", settled_blocked_min_range_m,
                    text("While following, once 1.6 m along a corridor, a blocked-near column's sector assumes a thing this far away instead of --blocked-min-range, which then holds for setting off, turning and the first metres (metres; 0: --blocked-min-range everywhere, the default; with --blocked-min-range 0.45, 0.6 here kept a 45-minute run off the carpeted middle corridor's wall but left another shuttling in one place; docs/explore.md, session 27)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 5.0));
    cmd->add_option("--setoff-blocked-min-range", setoff_blocked_min_range_m,
                    text("From a start or a recovery scan until following has come 1.6 m along the corridor set off into (or the first turn), a blocked-near column's sector assumes a thing this far away instead of --blocked-min-range: the robot knows nothing of the floor it never saw, and a column 0.36 m from the disc's flank and a corner 0.38 m away were met setting off (metres; 0: off; 0.45 by default since session 28: seeded starts 3 of 4,120 runs meet something against 5, the 45-minute traces of the main job's world unchanged; docs/explore.md, session 28)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 5.0));
    cmd->add_flag("--setoff-near-edges,!--no-setoff-near-edges", setoff_near_edges,
                  text("While --setoff-blocked-min-range holds, range the vertical edges of the visual sonar's frame above the horizon by the parallax of the robot's own travel, and remember those inside the blind range beside columns that show no floor step as points that floor seen later does not erase: a robot started 0.35 m from corridor-9's convex corner, whose painted face has the floor's grey, knew something stood there but not how near, and met it with its flank (on by default since session 32; docs/explore.md, session 32)"));
    cmd->add_option("--setoff-standing-hold", setoff_standing_hold_m,
                    text("While --setoff-blocked-min-range holds, the blocked-near columns of a near thing's edge (a run of them that ends in floor running far, not beside a floor step near the blind range) held over the last half second (--blocked-hold) count outside the latest view too where they were seen within this distance of where the robot stands: turning in place, it has not moved away from them. A robot started 0.35 m from corridor-9's convex corner turned away from it until the corner left the view, drove off and met it with its flank; 0.02 clears that start, but the obstacle course's start 1 of seed 4 then turns away from an edge on one side into a column on the other (metres; 0: off, the default; docs/explore.md, session 33)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_flag("--mirror-watch,!--no-mirror-watch", mirror_watch,
                  text("Watch the visual sonar for the robot's own reflection, a disc of its radius that moves as the robot's position mirrored in a plane (it comes nearer at twice the robot's speed), which nothing standing does; where it shows, remember a wall on the mirror's plane that the floor seen through the mirror does not erase: a mirror shows the corridor going on behind its base, and corridor-5's robot weaved into its mirror end (on by default since session 29; docs/explore.md, session 29)"));
    cmd->add_flag("--reopen-blocked-driven,!--no-reopen-blocked-driven", reopen_blocked_driven,
                  text("A corridor the robot has driven that it found blocked right after setting off along it (the stall guard) is closed for the rest of that visit to the node only, and open again (explored) on the next arrival: the robot stood where it could not set off (inside a side branch's mouth), which says nothing of the corridor. Without it a T's bar closed that way from its stem left the robot shuttling between the stem's dead end and the T for the rest of the run (docs/explore.md, session 35)"));
    cmd->add_option("--branch-line-spacing", branch_line_spacing_m,
                    text("The wall line that tells an opening's floor edge from the wall (the median of a side's last 15 abeam readings) takes its readings at least this far apart in travel (metres): one per step they span 0.3 m, and a pair of stray points inside a brick wall became the line, so the wall beyond them ended early and the robot stopped at the carpeted middle corridor's near corner (0: one per step, the default; docs/explore.md, session 41)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_flag("--feel-contacts,!--no-feel-contacts", feel_contacts,
                  text("Feel a contact from the wheels: commanded forward on two steps in a row while odometry shows (almost) no progress, something stands against the disc's front where the camera cannot see it; remember it as a point the floor seen later does not erase, reverse up to 0.1 m along the way just driven (the one reversal that is not blind) and look and choose as at any blockage (on by default since session 30; docs/explore.md, session 30)"));
    cmd->add_option("--contact-frames", contact_frames,
                    text("--feel-contacts: how many steps in a row (30 Hz) commanded forward without wheel progress make a contact. The simulator's robot reaches a commanded speed at once; on a real robot cover the drive's spin-up from standstill, or every start is felt as a contact (2 by default)"))
        ->capture_default_str()
        ->check(CLI::Range(1, 100));
    cmd->add_option("--blind-points-from", blind_points_from_m,
                    text("A visual-sonar column blocked near is also remembered for 5 s (--blind-points-keep) as soft points along its ray from this range (metres) out to the blind range, where the floor was not seen (0: off; 0.6 by default)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 5.0));
    cmd->add_option("--blind-points-keep", blind_points_keep_s,
                    text("With --blind-points-from: soft points are forgotten after this many seconds (5 by default)"))
        ->capture_default_str()
        ->check(CLI::Range(0.1, 600.0));
    cmd->add_option("--blind-points-edge-keep", blind_points_edge_keep_s,
                    text("With --blind-points-from: the soft points of a near thing's edge (a run of blocked-near columns with no floor step near the blind range beside it and floor running on beyond that on at least one side: a convex corner or an obstacle's side, not a wall running on into the blind zone nor one filling the view) are forgotten after this many seconds instead, long enough to outlast a full look around in place at the scan rate (10.5 s) and the alignment after it (0: as the others; 15 by default since session 39; docs/explore.md, sessions 37 and 39)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 600.0));
    cmd->add_flag("--blind-points-edge-keep-driving-only,!--no-blind-points-edge-keep-driving-only",
                  blind_points_edge_keep_driving_only,
                  text("With --blind-points-edge-keep: an edge's soft points kept past --blind-points-keep stop and steer the robot but are left out of the judgements of walls and openings (the side walls abeam and the centring on them, a side opening's depth, an end, a side's probe): kept for every query they moved those judgements and the route with them, and at 45 minutes `default` missed its middle corridor on 2 of 8 seeds (on by default since session 39; docs/explore.md, sessions 38 and 39)"));
    cmd->add_option("--side-wall-cluster", side_wall_cluster_m,
                    text("A side wall seen abeam (the side branches' wall runs and lines) is the nearest remembered point with another within this many metres of it, not one isolated point: one point 0.25 m inside a wall moved that wall's line inward, and the robot stopped for a false opening 2 m before an L corner and turned there (0: the nearest point; 0.15 by default since session 23; docs/explore.md, session 23)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_flag("--floor-edge-band-mouth,!--no-floor-edge-band-mouth", floor_edge_band_mouth,
                  text("With --floor-edge-openings: the floor-edge band cleared from the memory when the robot turns into such an opening spans only the opening (from where that side's wall ended, for its width), not the stop's surroundings: stopped short of a T's centre, the band reached back over the corridor's own wall, cleared its end, and the robot met the corner (on by default since session 23; docs/explore.md, session 23)"));
    cmd->add_option("--guard-unknown", guard_unknown_step_m,
                    text("Forward travel stops where the robot's disc, moved this many metres ahead, would cover floor beside its path never known free (floor not seen there, no sonar column's floor showing across it from the bottom row, the robot never on it): the camera sees nothing beside the robot, and a box or column that left the view in the near blind zone was met with the robot's flank (0: off, the default. It does not catch those flank contacts: on the three obstacle-course starts it seemed to fix it never fires after the first 0.5 m of travel, and the route taken after its stops at the start missed the obstacles; a robot started near a wall, whose blind zone the camera never sees free, stands still, and the seeded starts' coverage fell from 0.776 to 0.739 on seeds 1-8; docs/explore.md, sessions 24 and 25)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--guard-unknown-after", guard_unknown_after_m,
                    text("With --guard-unknown: the guard only once the wheels have travelled this many metres since the start (0: from the start; docs/explore.md, session 25)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1000.0));
    cmd->add_flag("--far-edge-on-line,!--no-far-edge-on-line", far_edge_on_line,
                  text("With --floor-edge-openings: a side opening's far edge is a remembered point on that side's wall line (within the tolerance), where the wall resumes, the branch's far corner or an end wall lies, not one inside the branch: a cluster of points 0.6 m inside a dead end's mouth made it a door recess (off by default: on, `default`'s 45-minute run of seed 12 covers 0.999 instead of 0.918, but seeds 5, 8 and 11 of 16 miss the middle corridor on routes that part at the first junction; docs/explore.md, session 24)"));
    cmd->add_option("--branch-coarse-from", branch_coarse_from_m,
                    text("A remembered point beyond a side's wall line, last seen from farther than this many metres, neither ends that side's opening nor blocks its free-across test: seen through a mouth from afar, a branch's far wall's base is ranged up to a row short (0.5 m at 4 m) and lies inside the branch, and `default`'s south stem read as a door recess (45-minute seeds 11 and 16) (0: off, the default; docs/explore.md, session 38)"))
        ->capture_default_str()
        ->check(CLI::Range(0.0, 100.0));
    cmd->add_flag("--scan-blind-start,!--no-scan-blind-start", scan_blind_start,
                  text("At the start, a view blind to the visual sonar (nearly all columns blocked near) is not taken for a corridor whatever the glance says: the robot looks all around first (on by default since session 18; docs/explore.md, session 18)"));
    cmd->add_flag("--rearm-after-gap,!--no-rearm-after-gap", rearm_after_gap,
                  text("A break in a side wall handled as an opening (a door recess rejected, a junction) starts a new wall run, however short it was, so the next side branch along that wall is still found (on by default since session 17; docs/explore.md, sessions 16 and 17)"));
  }
};

struct ExploreCliOptions {
  std::string world = "default";
  double minutes = 45.0;
  std::uint64_t seed = 1;
  std::string out = "explore-out";
  int eval_start = -1;  // >= 0: start i of `squint eval explore --seed SEED` (its pose and noise seed)
  std::string calib;    // corridor options YAML (`squint calibrate`'s file); empty: the defaults
  ExplorerVariants variants;
};

void RunExploreCommand(const ExploreCliOptions& opt) {
  const sim::World world = sim::LoadWorld(opt.world);
  eval::ExploreRunOptions run_opt;
  run_opt.minutes = opt.minutes;
  run_opt.seed = opt.seed;
  if (!opt.calib.empty()) run_opt.perception = config::LoadCorridorOptions(opt.calib);
  opt.variants.Apply(run_opt);
  if (opt.eval_start >= 0) {
    // The same start pose and noise seed as run `eval_start` of `squint eval explore --seed SEED`.
    run_opt.start = eval::SeededStarts(world, opt.eval_start + 1, opt.seed).back();
    run_opt.seed = opt.seed + static_cast<std::uint64_t>(opt.eval_start);
  }
  if (std::string e = run_opt.Validate(); !e.empty()) throw Error("explore: --minutes/--seed: " + e);
  io::StagedDirectory staged(opt.out);
  ProgressBar bar("explore " + world.name, 1000);
  const eval::ExploreRunResult run =
      eval::RunExplore(world, run_opt, [&](double f) { bar.Update(static_cast<std::size_t>(f * 1000.0)); });
  bar.Finish();
  eval::WriteExploreOutputs(staged.Path(), world, run);
  staged.Commit();
  const eval::ExploreSummary& s = run.summary;
  std::cout << s.outcome << "\n";
  std::printf("sim %.0f s, wall %.1f s, perception CPU %.2f s (%.3f%% of simulated time), %ld/%ld frames fully processed\n",
              s.sim_seconds, s.wall_seconds, s.perception_cpu_seconds, 100.0 * s.perception_cpu_seconds / s.sim_seconds,
              s.frames_fully_processed, s.frames);
  std::cout << "wrote " << (std::filesystem::path(opt.out) / "summary.json").string() << ", map.png, trace.csv, events.csv\n";
}

struct EvalExploreOptions {
  std::vector<std::string> worlds;
  int starts = 10;
  double minutes = 5.0;
  std::uint64_t seed = 1;
  std::string out = "explore-eval";
  std::string calib;  // as ExploreCliOptions::calib
  ExplorerVariants variants;
};

std::string Fixed(double v, int d) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", d, v);
  return b;
}

// A CSV cell: empty for NaN.
std::string Cell(double v, int d) { return std::isfinite(v) ? Fixed(v, d) : std::string(); }
// A text cell, as events.csv writes its notes: commas become semicolons (the project's CSV reader
// and tools/eval_explore_seeds.sh split on every comma).
std::string CsvText(std::string t) {
  std::replace(t.begin(), t.end(), ',', ';');
  return t;
}

void RunEvalExplore(const EvalExploreOptions& opt) {
  std::vector<std::string> names = opt.worlds;
  if (names.empty()) names = sim::BuiltinWorldNames();
  std::vector<sim::World> worlds;
  for (const std::string& n : names) worlds.push_back(sim::LoadWorld(n));
  corridor::CorridorOptions perception;
  if (!opt.calib.empty()) perception = config::LoadCorridorOptions(opt.calib);
  io::StagedDirectory staged(opt.out);
  ProgressBar bar("eval explore", names.size() * static_cast<std::size_t>(opt.starts));
  std::size_t done = 0;
  std::string table =
      "| world | start | x, y, yaw | minutes | distance m | coverage | ends | turns | collisions | outcome |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  // The columns after `proceeded` (empty when nothing was measured) are against ground truth: see
  // ExploreSummary's setoff_*, axis_error_* and first_* (the first contact and what it touched);
  // mirror_scans counts the sonar scans that showed the robot's own reflection (--mirror-watch);
  // contacts_felt the contacts the robot felt from its wheels (--feel-contacts); near_edges the edges
  // ranged inside the blind range while setting off (--setoff-near-edges); align_line_overrides how
  // often the walls' lines overrode the glance at a standstill (--wall-line-align-over);
  // scan_entropy_skips the scans whose choice of direction --scan-entropy-floor changed;
  // wall_keep_frames the following frames whose heading --wall-keep bounded;
  // scan_wall_entropy_skips the scans whose choice of direction --scan-wall-entropy changed.
  std::string csv =
      "world,start,x_m,y_m,yaw_deg,sim_seconds,distance_m,coverage,ends_detected,turns,collisions,proceeded,"
      "setoff_s,setoff_axis_error_deg,axis_error_p90_deg,axis_error_over_10deg,first_collision_s,first_hit,mirror_scans,contacts_felt,near_edges,"
      "align_line_overrides,scan_entropy_skips,wall_keep_frames,scan_wall_entropy_skips\n";
  std::map<std::string, int> first_hits;  // world: what, -> runs whose first contact it was
  int total_collisions = 0, runs = 0, clean = 0;
  int off_axis_runs = 0, setoff_off = 0;  // runs with following frames; set-offs more than 10° off the axis
  double off_axis_sum = 0.0;
  for (const sim::World& world : worlds) {
    const std::vector<Pose2> starts = eval::SeededStarts(world, opt.starts, opt.seed);
    for (int i = 0; i < static_cast<int>(starts.size()); ++i) {
      eval::ExploreRunOptions ro;
      ro.minutes = opt.minutes;
      ro.seed = opt.seed + static_cast<std::uint64_t>(i);
      ro.start = starts[i];
      ro.keep_trace = false;
      ro.perception = perception;
      opt.variants.Apply(ro);
      if (std::string e = ro.Validate(); !e.empty()) throw Error("eval explore: " + e);
      const eval::ExploreRunResult run = eval::RunExplore(world, ro);
      const eval::ExploreSummary& s = run.summary;
      const std::string kind = i == 0 ? "world start" : i == 1 ? "facing a wall" : i == 2 ? "close to a wall" : "random";
      table += "| " + world.name + " | " + std::to_string(i) + " " + kind + " | " + Fixed(starts[i].x, 1) + ", " +
               Fixed(starts[i].y, 1) + ", " + Fixed(RadToDeg(starts[i].yaw), 0) + " | " + Fixed(s.sim_seconds / 60.0, 1) +
               " | " + Fixed(s.distance_m, 0) + " | " + Fixed(s.coverage, 2) + " | " + std::to_string(s.ends_detected) +
               " | " + std::to_string(s.turns) + " | " + std::to_string(s.collisions) + " | " +
               (s.proceeded ? "explored" : "could not proceed") + " |\n";
      csv += world.name + "," + std::to_string(i) + "," + Fixed(starts[i].x, 3) + "," + Fixed(starts[i].y, 3) + "," +
             Fixed(RadToDeg(starts[i].yaw), 2) + "," + Fixed(s.sim_seconds, 1) + "," + Fixed(s.distance_m, 2) + "," +
             Fixed(s.coverage, 4) + "," + std::to_string(s.ends_detected) + "," + std::to_string(s.turns) + "," +
             std::to_string(s.collisions) + "," + (s.proceeded ? "1" : "0") + "," + Cell(s.setoff_seconds, 2) + "," +
             Cell(s.setoff_axis_error_deg, 2) + "," + Cell(s.axis_error_p90_deg, 2) + "," + Cell(s.axis_error_over_10deg, 4) +
             "," + Cell(s.first_collision_s, 2) + "," + CsvText(s.first_hit) + "," + std::to_string(s.mirror_scans) + "," +
             std::to_string(s.contacts_felt) + "," + std::to_string(s.near_edges) + "," +
             std::to_string(s.align_line_overrides) + "," + std::to_string(s.scan_entropy_skips) + "," +
             std::to_string(s.wall_keep_frames) + "," + std::to_string(s.scan_wall_entropy_skips) + "\n";
      if (!s.first_hit.empty()) ++first_hits[world.name + ": " + s.first_hit];
      if (std::isfinite(s.axis_error_over_10deg)) {
        off_axis_sum += s.axis_error_over_10deg;
        ++off_axis_runs;
      }
      if (std::isfinite(s.setoff_axis_error_deg) && std::abs(s.setoff_axis_error_deg) > 10.0) ++setoff_off;
      total_collisions += s.collisions;
      ++runs;
      if (s.collisions == 0) ++clean;
      if (i == 0) eval::WritePng(staged.Path() / ("map-" + world.name + ".png"), eval::DrawExploreMap(world, run));
      bar.Update(++done);
    }
  }
  bar.Finish();
  std::string footer = "\n" + std::to_string(clean) + " of " + std::to_string(runs) +
                             " runs without collision (" + std::to_string(total_collisions) + " collisions in all)\n" +
                             "axis (against ground truth): " + std::to_string(setoff_off) +
                             " set-offs more than 10 deg off; following, " +
                             Fixed(off_axis_runs > 0 ? 100.0 * off_axis_sum / off_axis_runs : 0.0, 1) +
                             "% of the frames more than 10 deg off (mean over runs)\n";
  std::string contacts;
  for (const auto& [what, n] : first_hits) contacts += (contacts.empty() ? "" : "; ") + what + " " + std::to_string(n);
  if (!contacts.empty()) footer += "first contacts (runs): " + contacts + "\n";
  io::WriteFileAtomically(staged.Path() / "table.md", table + footer);
  io::WriteFileAtomically(staged.Path() / "runs.csv", csv);
  staged.Commit();
  std::cout << table << footer;
}

struct CompareExploreOptions {
  std::string base, next;
  std::string out;  // optional: the report also written here
};

void RunCompareExplore(const CompareExploreOptions& opt) {
  const std::vector<eval::ExploreRunRow> base = eval::LoadExploreRuns(opt.base);
  const std::vector<eval::ExploreRunRow> next = eval::LoadExploreRuns(opt.next);
  eval::ExploreComparison c;
  try {
    c = eval::CompareExploreRuns(base, next);
  } catch (const Error& e) {
    throw Error(opt.base + " against " + opt.next + ": " + e.what());
  }
  const std::string report = eval::FormatExploreComparison(c, opt.base, opt.next);
  if (!opt.out.empty()) io::WriteFileAtomically(opt.out, report);
  std::cout << report;
}

struct SonarViewOptions {
  std::string world = "default";
  std::string pose;  // X,Y,YAW_DEG
  std::string png;   // optional: the sonar frame
  bool grey = false; // print the frame's grey levels instead of the columns
};

// One sonar frame at a pose, as the explorer's runner renders it (64×48, cropped to 4 rows above
// the horizon, 2×2 supersampling, sensor noise), and its columns: a diagnostic for the sonar.
void RunSonarView(const SonarViewOptions& opt) {
  const sim::World world = sim::LoadWorld(opt.world);
  Pose2 pose = world.start;
  if (!opt.pose.empty()) {
    double x = 0.0, y = 0.0, yaw_deg = 0.0;
    char c1 = 0, c2 = 0;
    std::istringstream in(opt.pose);
    if (!(in >> x >> c1 >> y >> c2 >> yaw_deg) || c1 != ',' || c2 != ',' || !std::isfinite(x) || !std::isfinite(y) ||
        !std::isfinite(yaw_deg))
      throw Error("eval sonar: --pose '" + opt.pose + "' must be X,Y,YAW_DEG");
    pose = Pose2{x, y, DegToRad(yaw_deg)};
  }
  const eval::ExploreRunOptions run_opt;
  const CameraModel cam = eval::BelowHorizon(world.camera.Model().Scaled(run_opt.sonar_width, run_opt.sonar_height));
  sim::RenderOptions ro;
  ro.supersample = run_opt.sonar_supersample;
  ro.noise_sigma = run_opt.sensor_noise_sigma;
  ro.seed = run_opt.seed + 1000003u;
  sim::Renderer renderer(world, cam, ro);
  cv::Mat image(cam.height, cam.width, CV_8UC1);
  MutableGrayView view{image.data, image.cols, image.rows, static_cast<std::ptrdiff_t>(image.step)};
  renderer.Render(pose, view, nullptr, 0, nullptr, 0, 0);
  explore::VisualSonar sonar(cam, run_opt.sonar);
  const auto& cols = sonar.Process(view);
  if (opt.grey) {
    for (int v = 0; v < image.rows; ++v) {
      std::cout << fmt::format("{:2d}", v);
      for (int u = 0; u < image.cols; ++u) std::cout << fmt::format(" {:3d}", image.at<std::uint8_t>(v, u));
      std::cout << "\n";
    }
    return;
  }
  static const char* kKinds[] = {"boundary", "blocked_near", "far", "unknown"};
  std::cout << "column,bearing_deg,kind,range_m,boundary_row,floor_edge_m\n";
  for (std::size_t u = 0; u < cols.size(); ++u) {
    const explore::SonarColumn& c = cols[u];
    std::cout << fmt::format("{},{:.1f},{},{:.2f},{},{:.2f}\n", u, RadToDeg(c.bearing_rad),
                             kKinds[static_cast<int>(c.kind)], c.range_m, c.boundary_row, c.floor_edge_m);
  }
  if (!opt.png.empty()) {
    cv::Mat big;
    cv::resize(image, big, cv::Size(), 8, 8, cv::INTER_NEAREST);
    std::vector<unsigned char> buf;
    cv::imencode(".png", big, buf);
    io::WriteFileAtomically(opt.png, std::string(buf.begin(), buf.end()));
  }
}

void Register(CLI::App& root) {
  auto opt = std::make_shared<ExploreCliOptions>();
  CLI::App* cmd = root.add_subcommand(
      "explore", "Explore a simulated building in closed loop from the camera (and wheel odometry) alone");
  cmd->add_option("--world", opt->world, "Built-in world name or world YAML file")->capture_default_str();
  cmd->add_option("--minutes", opt->minutes, "Simulated minutes (the run is bounded by this)")
      ->capture_default_str()
      ->check(kPositive);
  cmd->add_option("--seed", opt->seed, "Seed for odometry and sensor noise")->capture_default_str();
  cmd->add_option("--out", opt->out, "Output folder: summary.json, map.png, trace.csv, events.csv")->capture_default_str();
  cmd->add_option("--eval-start", opt->eval_start,
                  "Run start I of `squint eval explore --seed SEED` (its start pose and noise seed) with full outputs")
      ->check(CLI::Range(0, 999));
  cmd->add_option("--calib", opt->calib,
                  "Corridor options YAML, as `squint calibrate` writes it (include/squint/config/corridor_yaml.hpp); "
                  "default: the built-in options")
      ->check(CLI::ExistingFile);
  opt->variants.AddFlags(cmd, true);
  cmd->callback([opt] { RunExploreCommand(*opt); });

  auto eopt = std::make_shared<EvalExploreOptions>();
  CLI::App* eval_cmd = GetOrAddSubcommand(root, "eval", "Evaluate against ground truth and write reports");
  CLI::App* ex = eval_cmd->add_subcommand("explore", "Seeded starts per world (incl. facing and close to a wall): table and maps");
  ex->add_option("--world", eopt->worlds, "World name or file (repeatable); default: every built-in world");
  ex->add_option("--starts", eopt->starts, "Starts per world")->capture_default_str()->check(CLI::Range(1, 1000));
  ex->add_option("--minutes", eopt->minutes, "Simulated minutes per start")->capture_default_str()->check(kPositive);
  ex->add_option("--seed", eopt->seed, "Seed of the start poses and noise")->capture_default_str();
  ex->add_option("--out", eopt->out, "Output folder: table.md, runs.csv, map-WORLD.png")->capture_default_str();
  ex->add_option("--calib", eopt->calib, "As `squint explore`")->check(CLI::ExistingFile);
  eopt->variants.AddFlags(ex, false);
  ex->callback([eopt] { RunEvalExplore(*eopt); });

  auto copt = std::make_shared<CompareExploreOptions>();
  CLI::App* cmp = eval_cmd->add_subcommand(
      "compare-explore",
      "Two sets of `eval explore` runs compared run by run: per world coverage, distance and collisions, "
      "changed runs, runs failing in one set only");
  cmp->add_option("BASE", copt->base,
                  "Baseline: a runs.csv, a folder holding one, or a folder of seed-S/ folders (tools/eval_explore_seeds.sh)")
      ->required();
  cmp->add_option("NEW", copt->next, "The variant, the same way (its runs are matched by seed folder, world and start)")
      ->required();
  cmp->add_option("--out", copt->out, "Also write the report (Markdown) to this file");
  cmp->callback([copt] { RunCompareExplore(*copt); });

  auto sopt = std::make_shared<SonarViewOptions>();
  CLI::App* sv = eval_cmd->add_subcommand("sonar", "One visual-sonar frame at a pose: its columns as CSV (a diagnostic)");
  sv->add_option("--world", sopt->world, "Built-in world name or world YAML file")->capture_default_str();
  sv->add_option("--pose", sopt->pose, "X,Y,YAW_DEG (default: the world's start)");
  sv->add_option("--png", sopt->png, "Also write the sonar frame, magnified 8x");
  sv->add_flag("--grey", sopt->grey, "Print the frame's grey levels (one line per row) instead of the columns");
  sv->callback([sopt] { RunSonarView(*sopt); });
}

const CommandRegistrar kRegistrar(300, &Register);

}  // namespace
}  // namespace squint::app
