// The exploration state machine and motion controller (exploration paper §5.3, plus a
// topological map): scan to find the corridor, follow it centred, stop at its end, look to
// each side and tell an open corridor from a wall by entropy, turn, and prefer unexplored
// branches. Input: camera-derived Percepts and wheel odometry only; output: (v, ω) commands.
#pragma once

#include <deque>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "squint/explore/mirror_watch.hpp"
#include "squint/explore/near_edges.hpp"
#include "squint/explore/obstacle_memory.hpp"
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
  double axis_gain = 0.2;             // per processed frame
  double axis_outlier_deg = 20.0;     // innovations larger than this are ignored
  // Centring from the translation-sensitive cues: lateral cue = centre − fused heading.
  double centre_gain = 0.8;           // target heading = −centre_gain · lateral cue
  double centre_filter = 0.4;         // low-pass of the lateral cue per processed frame
  double max_centre_correction_deg = 10.0;
  // End of the corridor, two triggers (either stops the robot):
  // (a) the fused distance to the end, median of the last end_median_frames processed frames,
  //     below end_stop_dist_m;
  double end_stop_dist_m = 1.1;
  int end_median_frames = 9;
  // (b) the glance entropy falling below end_entropy_ratio × the corridor's reference entropy
  //     (paper §4.2.3: entropy drops as the end wall fills the view) on end_confirm_frames
  //     consecutive frames. In the simulator's corridors the ratio crosses 0.62 between 0.7 m
  //     and 1.7 m from the end wall.
  double end_entropy_ratio = 0.62;
  int end_confirm_frames = 5;
  double min_travel_before_end_m = 0.8;  // after a turn, before an end may be detected
  // Deciding by looking (entropy rule).
  double turn_rate_rps = 1.2;         // rotating in place
  double turn_tolerance_deg = 1.5;
  int settle_frames = 4;              // frames to wait after a rotation before looking
  int look_frames = 4;                // frames whose glance entropy is averaged
  // A node whose sides were both judged walls (a dead end) is looked at again on this many later
  // arrivals, instead of reusing that judgement: one misjudged look (the axis off at an L corner,
  // the opening read as a wall) otherwise closes the branch for the rest of the run. 0: never.
  int reprobe_dead_end_visits = 1;
  // A side is open when its entropy reaches this fraction of the reference entropy (a high
  // percentile of the glance entropy while following the corridor just driven, i.e. looking
  // down a corridor).
  double open_entropy_ratio = 0.85;
  int reference_window = 64;          // entropy samples (one per 0.15 m) kept for the reference
  double reference_percentile = 0.8;
  // Start-up scan (recovery when starting facing a wall or close to one): a full turn in place.
  // The corridor axis modulo 90° (Manhattan) is the mode of odometry yaw − fused heading over the
  // scan's processed frames; of its four directions the robot sets off along the one whose glance
  // entropy is highest (the paper: entropy peaks looking down the corridor).
  int scan_bins = 36;
  // The scan's choice of direction takes no free travel where the sonar's views (within one bin)
  // were mostly a wall filling the view (blocked near across it, the glance entropy below the
  // blind-view threshold): such a wall stands inside the blind range and is never remembered, so
  // the memory alone finds that direction the freest (corridor-6 start 2, 0.1 m from a wall,
  // set off into it). On by default since session 7, with axis_from_walls and
  // trust_memory_max_wall_lines (alone it moved default's 45-minute route at its NW corner to
  // coverage 0.85 on seed 1; the three together: seeded starts 119/120 and 114/120 on seeds 1 and
  // 2, default coverage 1.00 on both; docs/explore.md, session 7).
  bool scan_skips_wall_views = true;
  // With scan_skips_wall_views, a scan's view whose sonar frame shows periodic horizontal lines
  // in at least this fraction of its column bands (Percept::sonar_wall_lines) counts as a wall
  // view too: a brick wall up close, whose mortar the sonar reads as floor running far (corridor-9,
  // a start 0.65 m from the brick side wall: no column blocked, the scan set off into it).
  // 0 turns it off (`squint explore --scan-wall-lines 0`); 0.75 since session 19.
  double scan_wall_lines = 0.75;
  // > 0: of the four directions along the scan's axis, one that the memory finds free to the
  // scan's full reach (3 m: nothing ranged there) and whose glance entropy (the mean over its bin
  // and the two beside it) lies below this fraction of the highest of the four is not taken.
  // Starting 0.7 m from a door in corridor-7's side wall the door read as a corridor view
  // (blocked-near columns forgotten as unknown), so the memory found it the only free direction,
  // while the corridor's two directions were closed by the near wall's columns seen askance on the
  // turn; its entropy was 0.83 of the corridor's and the robot drove into the door (start 4 of seed
  // 23 with wall_line_align_over_deg 25). Directions with something ranged in them are left to the
  // free travel: skipping those too (tried in session 43) kept corridor-1's start 4 of seed 29
  // from setting off along its narrow cross corridor toward a dead end (entropy 0.886 of the
  // other way), and it met the wall. A run whose scans never lose their choice to this is the run
  // without it step for step (scan_entropy_skips counts those that do). `squint explore
  // --scan-entropy-floor R`; docs/explore.md, sessions 43 and 45. 0.9 since session 45 (0: off).
  double scan_entropy_floor = 0.9;
  // A scan takes no axis direction whose glance entropy is below this fraction of the best of the
  // four, whatever its free travel, while another direction (not skipped by scan_entropy_floor) is
  // left (0: off; 0.7 since session 49). A brick wall 0.4 m away gives the glance a wall's low entropy (0.63
  // of the best) while its mortar courses, taken for floor boundaries, range it 1.2-1.5 m off: the
  // free travel then outscored the directions the near walls and an axis 20° off left 0.25-0.3 m
  // of (corridor-9's starts 4 of seed 40 and 5 of seed 67, near the T's bar). `squint explore
  // --scan-wall-entropy R`; docs/explore.md, sessions 47 and 49.
  double scan_wall_entropy = 0.7;
  // The corridor axis checked against the walls the memory holds (ObstacleMemory::WallAxisMod90,
  // trusted with at least wall_axis_min_pairs pairs and wall_axis_min_strength): a scan takes the
  // walls' axis where the glance's differs from it by more than 10 degrees, a probe first snaps
  // the axis to it when they differ by that much, and while following (after 1 m in the
  // corridor) each sonar frame moves the axis by wall_axis_gain of a difference above 8 degrees.
  // The glance's heading drifts 15-35 degrees near corridor-9's T (start 5 cut the mouth's corner)
  // and a re-scan at default's NW corner found the diagonals. On by default since session 7 (see
  // scan_skips_wall_views; alone: default's seed-2 coverage 1.00 but seed 1's 0.85).
  bool axis_from_walls = true;
  int wall_axis_min_pairs = 40;
  double wall_axis_min_strength = 0.6;
  double wall_axis_gain = 0.2;
  double scan_rate_rps = 0.6;
  // Axis re-acquisition: after this many consecutive outlier innovations, the axis is reset to
  // their median (the corridor frame was lost).
  int axis_reacquire_frames = 12;
  // When > 0 and the percept carries the heading filter's estimate (Percept::heading_filtered_deg),
  // an inlier frame (per-frame heading within axis_outlier_deg) moves the axis by this gain toward
  // the filtered heading's axis instead of by axis_gain toward the per-frame one. Outliers and
  // re-acquisition still use the per-frame heading, and TakeHeadingFilterReset() asks the caller
  // to restart the filter wherever the axis it is relative to changes. 0: off. 0.2 since session
  // 12 (an option since session 10; `squint explore --no-heading-filter` sets 0; docs/explore.md).
  double filtered_axis_gain = 0.2;
  // With the filter: a new corridor's filter starts from the heading the explorer's own axis
  // implies (odometry yaw − axis: exact after a turn by odometry from a good axis) with this
  // standard deviation, instead of from the next frame's estimate (a mouth's first views can be
  // 10° off). After a re-acquisition it starts from the next frame. 0: never a prior. 3 since
  // session 12 (`squint explore --heading-prior-std`; docs/explore.md, sessions 11 and 12).
  double heading_filter_prior_std_deg = 3.0;
  // Alignment in place after the scan: take the median fused heading of align_frames fully
  // processed frames, rotate by it, repeat until below align_done_deg (at most align_rounds).
  int align_frames = 7;
  double align_done_deg = 2.0;
  int align_rounds = 4;
  // At the start the robot first looks where it faces: when the glance entropy reaches this
  // (a view down a corridor; views of a wall are far lower) and the fused headings agree, it
  // aligns and sets off without the scan, which near corners can lock onto a diagonal view.
  double start_corridor_entropy_nats = 2.7;
  // ...nor where the sonar's view at the start is blind (nearly all columns blocked near, read as
  // unknown because the glance looks like a corridor): a wall of the corridor's entropy within
  // the blind range passes the glance's tests (`default`, a start 0.5 m from a wall with a door
  // frame in view). On since session 18; off: `squint explore --no-scan-blind-start`.
  double start_max_spread_deg = 6.0;
  // Stall guard from odometry alone: commanded forward but the wheels did not move.
  double stall_window_s = 1.0;
  double stall_min_progress_m = 0.05;
  // Contact felt from the wheels (proprioception, no camera): commanded forward at least
  // contact_min_v_mps on contact_frames consecutive steps while odometry shows less than
  // contact_max_progress of the commanded travel. The thing stands against the disc's front,
  // where the camera cannot see it (inside the sonar's blind range, or beside the view). The
  // robot remembers it as a confirmed point contact_point_gap_m beyond the disc along the heading
  // (floor seen later does not remove it; age does), reverses up to contact_reverse_m along the
  // way it just drove forward (the disc was there a moment ago: the one reversal that is not
  // blind) and then looks and chooses as at any blockage. Without it a robot whose flank met a
  // box's corner out of view set off into it again after every scan (the obstacle course, start
  // 5 of seed 7: 172 steps in contact). Fires only in contact, so runs without any contact are
  // unchanged. On by default since session 30 (`squint explore --no-feel-contacts`).
  bool feel_contacts = true;
  double contact_min_v_mps = 0.1;
  // The simulator's unicycle reaches a commanded speed at once; a real drive needs time to spin
  // up from standstill, and contact_frames must cover it (`--contact-frames`), or every start is
  // felt as a contact.
  int contact_frames = 2;
  double contact_max_progress = 0.2;
  double contact_point_gap_m = 0.01;
  double contact_reverse_m = 0.1;
  // Obstacle override (used only when Percepts carry ObstacleAdvice): while the latest advice
  // (at most avoid_hold_s old) has an obstacle across the path, steer toward its free gap
  // (ω = avoid_gain · error to the gap's direction, held in the odometry frame) at
  // avoid_speed_fraction of cruise; on avoid_blocked_frames consecutive blocked advices, stop and
  // turn (probe both sides, as at a blockage). Clear advice hands back to corridor following.
  double avoid_gain = 1.5;
  double avoid_speed_fraction = 0.5;
  double avoid_hold_s = 0.5;
  int avoid_blocked_frames = 2;
  // An obstacle must be across the path on this many consecutive advices before the override
  // acts (single-pair false obstacles, e.g. floor joints, are common).
  int avoid_confirm_advices = 2;
  // Visual sonar (used when Percepts carry scans): remembered floor contacts limit the speed so
  // that the robot's disc stops before anything it saw, steer around obstacles, centre the
  // robot between the side walls, detect the corridor's end and tell open sides from walls.
  double robot_radius_m = 0.25;
  double safety_margin_m = 0.10;      // kept between the disc and anything remembered
  double stop_margin_m = 0.08;        // free travel left when the speed limit reaches zero
  double speed_per_free_mps = 1.2;    // v <= this (1/s) × (free travel − stop margin)
  double lookahead_m = 2.0;           // free travel that counts as "clear ahead"
  double gap_step_deg = 5.0;          // candidate headings around the desired one
  int gap_steps = 9;                  // per side
  double gap_cost_per_deg = 0.004;    // preference for the desired heading (score per degree)
  // Following: a side wall the memory holds abeam (the centring's side distances) within
  // gap_side_wall_max_m of the robot is taken to run on along the corridor's axis, so a candidate
  // heading toward it is free only until the disc (with safety_margin_m) would reach that line.
  // The memory holds what the sonar saw; a wall of the floor's grey ahead of the robot is often not
  // in it (corridor-2's panels over its carpet: the sonar reads them as floor), and a gap chosen
  // toward it drives the robot into it. Walls farther off are left out: the line would close the
  // openings of junctions and corners that a robot near the corridor's centre steers into.
  // 0 (the default) turns it off. 0.7 m (measured without reprobe_dead_end_visits): seeded starts
  // 933 of 960 on seeds 1-8 against 911, but the default world's 45-minute coverage fell on five
  // of eight seeds, to 0.35-0.86 (docs/explore.md, session 9).
  double gap_side_wall_max_m = 0.0;
  double sonar_end_free_m = 0.85;     // end of corridor: free travel along the axis below this...
  double sonar_end_gap_m = 1.5;       // ...and no candidate heading with this much free travel
  double sonar_open_free_m = 2.0;     // probing: a side is open when it is free this far...
  // ...and its look's glance entropy is at least this fraction of the reference entropy: a wall
  // inside the sonar's blind range whose base was read as floor from farther back (a brick wall's
  // mortar) shows free travel but a wall's entropy (0.60 and 0.65 of the reference where that
  // sent the robot into the west wall of `default`; every side truly open by the sonar in 16
  // `default` runs had 0.80 or more). 0 turns it off (`squint explore --no-sonar-open-entropy`);
  // 0.7 since session 12 (docs/explore.md).
  double sonar_open_min_entropy_ratio = 0.7;
  double sonar_centre_gain = 0.35;    // rad of target heading per metre of lateral offset
  double sonar_centre_max_lateral_m = 1.8;  // side points farther than this do not centre
  // Centring on the ceiling lights' line (Percept::light_lateral_m, paper §4.1.5's remark that
  // lights move with translation) in place of the sonar's side walls, at this gain (rad of target
  // heading per metre; 0: off, `squint explore --no-light-centring`; 0.35 since session 12). A reading
  // counts when its heading is within light_heading_gate_deg of the explorer's own and its offset
  // within light_max_lateral_m; the offset is used once light_confirm readings in a row agree
  // within light_agree_m (in the corridor frame, by odometry), and for light_hold_s after the last.
  double light_centre_gain = 0.35;
  double light_heading_gate_deg = 3.0;
  double light_max_lateral_m = 0.9;
  int light_confirm = 3;
  double light_agree_m = 0.15;
  double light_hold_s = 1.0;
  // The lights' line's heading (Percept::light_heading_deg, when a line was found in the frame)
  // also moves the corridor axis while following: by light_axis_gain of the difference on each
  // frame whose light heading lies within light_axis_gate_deg of the heading the explorer holds
  // (a line of a crossing corridor's lights, or of one row of two side rows, seldom does); within
  // light_hold_s of such a frame the glance's inlier headings leave the axis alone. On
  // rendered centre-row glances its heading is right to 0.7 deg (p90) where the glance's fused
  // heading scatters by degrees (`default`'s carpeted middle corridor). 0 turns it off (the
  // default; `squint explore --light-heading` sets 0.05; docs/explore.md, session 12).
  double light_axis_gain = 0.0;
  double light_axis_gate_deg = 10.0;
  // The lights' line's drift (session 13): the offsets from the lights' line (within
  // light_max_lateral_m, their line's heading within light_drift_gate_deg of the explorer's) at
  // the odometry positions where they were read, over the last light_drift_window_m of travel,
  // give the line's direction in the odometry frame by least squares (offset = across − along ·
  // tan δ); with at least light_drift_min_readings readings spanning light_drift_min_span_m, a
  // residual below light_drift_max_rms_m and |δ| ≤ light_drift_max_deg, each frame moves the axis
  // by light_drift_gain · δ. 0 turns it off.
  double light_drift_gain = 0.0;
  double light_drift_gate_deg = 12.0;
  double light_drift_window_m = 4.0;
  double light_drift_min_span_m = 2.0;
  int light_drift_min_readings = 10;
  double light_drift_max_rms_m = 0.06;
  double light_drift_max_deg = 12.0;
  // The walls' base lines from the floor's texture (Percept::wall_line_heading_deg, a 128×96
  // frame; wall_lines.hpp) steer the corridor axis while following. Each reading gives an axis
  // (odometry yaw − its heading, modulo 90° the one nearest the axis held) when it lies within
  // wall_line_gate_deg of it; once the last wall_line_confirm readings, each within
  // wall_line_hold_s of the next, agree within wall_line_agree_deg, each reading moves the axis by
  // wall_line_axis_gain of the difference to their median. Within wall_line_hold_s of such a move
  // the glance's headings leave the axis alone (neither inliers nor re-acquisition): where the
  // walls have the floor's grey the glance's cues scatter by 10° and more (corridor-2, `default`'s
  // carpeted middle corridor) while the lines read within 1–2°. A confirmed median within
  // wall_line_min_diff_deg of the axis leaves it alone (where the glance reads well the lines only
  // guard against its larger errors). 0 turns it off (`squint explore --no-wall-lines`); 0.2, the
  // default since session 17 (docs/explore.md, sessions 15-17).
  double wall_line_axis_gain = 0.2;
  double wall_line_gate_deg = 30.0;
  int wall_line_confirm = 3;
  double wall_line_agree_deg = 3.0;
  double wall_line_hold_s = 1.0;
  double wall_line_min_diff_deg = 4.0;
  // The walls' lines as free travel where the sonar sees no floor boundary. When at least half of
  // their frames of the last 0.5 s taken facing the direction (within 20°; taken while following
  // or probing) show both walls' lines with the robot between them, reading an axis within
  // wall_line_gate_deg of the one held modulo 90°, and no foot across the corridor nearer than this
  // (Percept::wall_line_corridor_ahead_m), then
  // (a) an end read by the visual sonar alone is not taken, and (b) a probed side is open when its
  // entropy passes sonar_open_min_entropy_ratio, as with the sonar's own free travel. Where the
  // floor has the walls' grey the sonar reads "blocked near" in part of its columns: `default`'s
  // carpeted middle corridor was read as an end 1.5 m into its mouth, and its mouth as a wall from
  // the west corridor. 0 turns it off (`squint explore --wall-line-free 0`); 2.5, the default since
  // session 17 (docs/explore.md, sessions 16-17).
  double wall_line_free_m = 2.5;
  // Keeping off a wall the lines show near (> 0: on). While setting off (wall_keep_setoff_only), a wall line read within
  // the last 0.5 s (Percept::wall_line_offset_m, moved by odometry since) lying within
  // wall_keep_gate_deg of the axis and nearer to the robot's centre than this (metres) bounds the heading: at most
  // wall_keep_gain_deg_per_m × (wall_keep_m − distance) degrees (wall_keep_max_deg at most) away
  // from the line's own direction, whatever the axis held says. The lines measure the wall where
  // the glance's heading is biased by a wall filling half the view and the visual sonar sees no
  // floor edge (corridor-2 97/2: 0.35 m from the wall, the glance's axis 7° off, set off 5° toward
  // it). 0 turns it off (`squint explore --wall-keep`; docs/explore.md, session 46); 0.45 since
  // session 49, with wall_keep_min_m 0.25 (docs/explore.md, sessions 47 and 49). The gate
  // leaves out lines farther off the axis than the axis can be wrong: a rotated box's base 27° off
  // it, 0.35 m to the right, turned the robot 30° left into another box (the obstacle course's
  // start 4 of seed 5, with a 30° gate).
  double wall_keep_m = 0.45;
  double wall_keep_gate_deg = 15.0;
  // A line nearer to the robot's centre than this (metres) is left out: no wall stands there while
  // the disc touches nothing (0: none left out). A line on the floor 0.18 m to the right, read as
  // the main line's parallel, turned the robot 21° left into the chair (the obstacle course's start
  // 7 of seed 67, with wall_keep_min_m 0). `squint explore --wall-keep-min`; docs/explore.md, session 47.
  // 0.25 since session 49.
  double wall_keep_min_m = 0.25;
  // Only while setting off (from the start or a look around in place until trust_memory_after_m of
  // following), where the failures it is for happen: applied all along, it bounded 1,314 frames of
  // the main job, whose route then passed the carpeted middle corridor (coverage 0.854).
  bool wall_keep_setoff_only = true;
  double wall_keep_gain_deg_per_m = 30.0;
  double wall_keep_max_deg = 10.0;
  // At the end of a corridor (not at a side branch or a blockage), a side the entropy rule calls
  // open (open_entropy_ratio) is also open where the remembered points alone leave it free for
  // sonar_open_free_m, whatever the latest scan's blocked-near columns say. With an axis held
  // exactly (wall_line_axis_gain) the robot arrives at an L corner's end wall instead of rounding
  // the corner, and looking into the branch from beside its mouth the near wall of the branch
  // stands inside the sonar's blind range: every `default` corner was a dead end. On by default
  // since session 17 (`squint explore --no-end-probe-memory`; docs/explore.md, sessions 15-17).
  bool end_probe_memory = true;
  // The walls' lines also set the axis at a standstill: in the start-up scan (and a re-acquiring
  // full turn) their readings' mode, modulo 90°, is the axis whatever the glance's candidates and
  // the remembered walls say; in the alignment the glance's median heading is moved to the lines'
  // heading modulo 90° nearest it (the glance in a carpeted corridor can read 30-45° off). Needs
  // the lines' frames while scanning and aligning (eval::RunExplore renders them when this is on
  // and wall_line_axis_gain > 0). `squint explore --wall-line-align`; docs/explore.md, session 17.
  bool wall_line_align = false;
  // > 0 (degrees), without wall_line_align: the walls' lines are read while scanning and aligning
  // too, but set the axis there only where they disagree with the glance by more than this: in the
  // start-up scan where their mode lies this far from the axis the glance and the remembered walls
  // give (or those give none), in the alignment where the lines' heading nearest the glance's
  // median lies this far from it. Where they agree the run is the run without it step for step. With 25
  // the set-offs 28-44 degrees off the axis that met things (corridor-8 61/2, the obstacle course
  // 100/5 and 43/8, `default` 74/4) are corrected in replays, and the set-offs that wall_line_align
  // moved by a few degrees toward a chair or a floor-grey wall are left alone; but on seeds 1-48 of
  // the seeded starts it cleared one failure and added two (runs whose route an override changed),
  // and at 45 minutes it missed seed 14's middle corridor. `squint explore --wall-line-align-over D`;
  // docs/explore.md, sessions 42 and 45. 25 since session 45 (0: off).
  double wall_line_align_over_deg = 25.0;
  double rescan_yaw_deg = 12.0;       // no forward motion until a scan was taken at the heading
  // Following: after this travel in the corridor the latest scan's blocked-near columns block only
  // the narrow sector at the blind range, and those along which the floor in the blind zone was
  // seen from farther back are ignored...
  double trust_memory_after_m = 1.6;
  // While following, once the robot has come trust_memory_after_m along the corridor, a
  // blocked-near column's sector assumes a thing this far away (metres) instead of the memory's
  // blocked_min_range_m, which then holds for setting off, turning and the first metres only.
  // Session 27: with blocked_min_range_m 0.45 everywhere, a 45-minute run (seed 12) took the wider
  // sectors for headings more than 45° off the axis and turned off the carpeted middle corridor's
  // axis into its unseen wall; 0.6 here fixed that run, but seed 2's 45 minutes then shuttled in
  // one place (coverage 0.206). 0: the memory's blocked_min_range_m everywhere (the default;
  // docs/explore.md, session 27).
  double settled_blocked_min_range_m = 0.0;
  // From a start or a recovery scan (the robot looked around where it stands, and knows nothing of
  // the floor it never saw) until following has come trust_memory_after_m along the corridor it
  // set off into, or the first turn, a blocked-near column's sector assumes a thing this far away
  // (metres) instead of the memory's blocked_min_range_m: a column 0.36 m from the disc's flank
  // and a convex corner 0.38 m away were met setting off (obstacle course start 1 of seed 4,
  // corridor-9 start 2 of seed 17). A turn at a junction is not a set-off: the robot came along
  // and saw the mouth from farther back, and following keeps the memory's range (the nearer sector
  // everywhere drove a 45-minute run into a wall, session 27). 0: off. 0.45 by default since
  // session 28: seeded starts, seeds 1-32 and the obstacle course's 33-60, 3 of 4,120 runs meet
  // something against 5; the main job's and `default`'s 45-minute traces are unchanged
  // (`squint explore --setoff-blocked-min-range M`; docs/explore.md, session 28).
  double setoff_blocked_min_range_m = 0.45;
  // While setoff_blocked_min_range_m holds (from a start or scan until 1.6 m of following or a
  // turn), range the vertical edges the sonar frame shows above the horizon by the parallax of
  // the robot's own travel (NearEdgeRanger: two pairs of frames that must agree) and remember
  // those found within the blind range, beside sonar columns that show no floor step (two of the
  // three nearest on one side), as points that floor seen later does not erase. A robot started
  // 0.35 m from corridor-9's convex corner, whose painted face has the floor's grey, knew the
  // corner was there but not how near: it turned away until the face left the view and met the
  // corner with its flank (`squint explore --no-setoff-near-edges`; docs/explore.md, session 32).
  bool setoff_near_edges = true;
  NearEdgeOptions near_edges;
  // While setoff_blocked_min_range_m holds, the blocked-near columns of a near thing's edge
  // (ObstacleMemoryOptions::blocked_edge_step_m: a run of them that ends in floor running far, not
  // beside a floor step near the blind range) in the scans held over the last half second
  // (blocked_hold_s) count outside the latest scan's view too where they were seen within this
  // distance (metres) of where the robot stands: turning in place, it has not moved away from
  // them. blocked_hold_in_view drops a held column once it leaves the view, and a robot started
  // 0.35 m from corridor-9's convex corner, which it saw at the edge of its view, turned away
  // until the corner left the view and drove off with it 39 degrees to its left, into its flank
  // (start 2 of seed 45). Held in full (every blocked column, walls too), robots beside
  // corridor-1's brick walls never got under way. 0: off, the default: with 0.02 the obstacle
  // course's start 1 of seed 4, beside a column, turned away from an edge held on one side into
  // the column on the other (`squint explore --setoff-standing-hold M`; docs/explore.md, session 33).
  double setoff_standing_hold_m = 0.0;
  // Watch the visual sonar for the robot's own reflection (MirrorWatch: a disc of the robot's
  // radius that moves as the robot's position mirrored in a plane, not as anything standing
  // does) and, where it shows, remember a wall on the mirror's plane (confirmed points, which
  // floor seen through the mirror does not remove) mirror_wall_half_span_m to each side of where
  // the robot's line of sight meets it. A mirror shows the corridor going on behind its base, and
  // corridor-5's robot weaved into its mirror end (start 0 of seed 23). On by default since
  // session 29 (`squint explore --no-mirror-watch`; docs/explore.md, session 29).
  bool mirror_watch = true;
  double mirror_wall_half_span_m = 1.5;
  MirrorWatchOptions mirror;  // its body_radius_m is robot_radius_m
  // ...but not when the latest scan's frame shows wall lines (VisualSonar::WallLineFraction, brick
  // mortar) in at least this fraction of its bands: a brick wall ahead, whose base the sonar may
  // have read as floor from farther back. 0 turns it off. On (0.375) since session 7 with
  // scan_skips_wall_views and axis_from_walls; alone 0.375 and 0.625 fixed corridor-9 start 2 but
  // cost corridor-1 start 7 or corridor-9 start 7 (116/120 either way; docs/explore.md, session 6).
  double trust_memory_max_wall_lines = 0.375;
  // A sonar view whose columns are nearly all blocked near (at least blind_view_fraction) is either
  // a wall filling the view or a floor without any contrast to the walls (default's carpeted
  // middle corridor, corridor-2). The glance tells them apart: looking down a corridor its entropy
  // stays near the corridor's reference (ceiling lights, converging walls), while a wall within
  // the blind range fills the 32x24 view and its entropy drops. At or above
  // blind_view_entropy_ratio x the reference entropy the blocked-near columns are read as unknown
  // (no information: the memory and the stall guard remain); before any reference (start-up), at
  // or above start_corridor_entropy_nats. 0 turns this off.
  double blind_view_fraction = 0.75;
  double blind_view_entropy_ratio = 0.85;
  // A blind view taken within wall_view_hold_m of wheel travel, wall_view_hold_deg of yaw and
  // wall_view_hold_s of time of the last view judged a wall by its entropy is a wall too: the
  // glance's entropy facing a box up close hovers at the threshold, and one frame above it made
  // the box's columns unknown and let the robot drive on into it (the obstacle course, start 3 of seed 5). Only views judged walls by their entropy
  // are held from, so a robot standing still re-judges after wall_view_hold_s. Off by default
  // (`squint explore --wall-view-hold 0.1`): in `default`'s carpeted middle corridor the same
  // hovering entropy turns blind views into walls, and the 45-minute runs missed that corridor on
  // 8 of 32 seeds (1 without it; docs/explore.md, session 19).
  double wall_view_hold_m = 0.0;
  double wall_view_hold_deg = 10.0;
  double wall_view_hold_s = 1.0;  // ...and within this time of it (a robot standing still re-judges)
  bool blind_view_clears = true;  // such a view also clears the memory along its rays out to the blind range
  // Probing, a side whose latest scan was such a blind view read as unknown is not open by the
  // sonar's free travel (which then rests on no floor seen at all: a door recess within the blind
  // range whose door has the glance entropy of a corridor, corridor-5), only by the walls' lines,
  // the remembered points at a corridor's end, or the entropy rule on a side the sonar showed
  // open while following. Off: `squint explore --no-blind-side-lines`; on since session 18.
  bool blind_side_needs_lines = true;
  // Probing, a side whose scan facing it shows a brick wall's mortar lines in at least this
  // fraction of its bands (VisualSonar::WallLineFraction) is not open by the sonar's free travel:
  // a brick wall within the blind range reads its mortar lines as floor boundaries and its
  // lit face as floor, and the sonar showed 3 m free facing `default`'s east wall 0.6 m away
  // (start 2 of seed 17, lines 1.0, entropy 0.71 of the reference). No side open by the sonar in
  // seeds 1-4's 4,227 probes had more than 0.25. 0 turns it off (`squint explore --probe-wall-lines
  // 0`); 0.375 since session 25 (docs/explore.md).
  double probe_max_wall_lines = 0.375;
  // ...nor, at a corridor's end, open by the remembered points (end_probe_memory): a brick wall
  // inside the blind range leaves no point in the memory, and corridor-9's robot, stopped 2.2 m
  // before its T with the brick side wall 0.68 m away (lines 1.0, entropy 1.91 of the reference's
  // 2.22 where 1.89 is open), turned into it (start 7 of seed 38). On by default since session 31
  // (`squint explore --no-probe-wall-lines-memory`; docs/explore.md, session 31).
  bool probe_wall_lines_memory = true;
  bool scan_blind_start = true;  // see start_corridor_entropy_nats
  // An end read by the sonar with less than this free travel along the axis (metres) makes the
  // branch ahead a wall even where the map holds it explored (the robot came that way before): it
  // is blocked now, and "straight on" there drove the obstacle course's robot into a bin 0.5 m
  // ahead. 1.0 since session 18; 0 turns it off (`squint explore --sonar-end-blocks 0`).
  double sonar_end_blocks_m = 1.0;
  // Following toward a place the map holds as a dead end (a node whose branches ahead and to both
  // sides are walls; not an L corner or a T's bar, where creeping cost corridor-2's seeded starts
  // coverage 0.80 -> 0.74 in their 3 minutes) the robot creeps (min_speed_fraction of cruise)
  // from this far (metres of map travel) before the node's position to 1 m past it, whatever the glance and the sonar say: a mirror end wall
  // shows the corridor behind and the sonar reads floor running on, and on the second visit the
  // robot met corridor-5's mirror at full speed (start 2 of seed 6). 0 turns it off
  // (`squint explore --known-end-slow M`).
  double known_end_slow_m = 0.0;
  // With known_end_slow_m: creep only while the fused distance to the end exceeds the map's
  // distance to that dead end by more than this (metres): the mirror shows the corridor running
  // on, a plain end wall is read where the map holds it. 0: creep whatever the fused distance says.
  double known_end_disagree_m = 0.0;
  // In a blind view read as unknown (blind_view_entropy_ratio), a blocked-near sonar column stays
  // blocked near where the walls' lines' frame shows its bottom smooth: that column's mean bottom
  // texture (Percept::wall_bottom_texture) below this fraction of the floor's (the frame's 90th
  // percentile over its columns when at least blind_texture_min_floor grey levels, else the last
  // such reference within blind_texture_hold_s). A panel of the carpet's grey within the blind
  // range is smooth, the carpet is not (corridor-2: a robot started close to a wall, heading
  // into it). With blind_texture_unknown, outside blind views the sonar's own unknown columns
  // (no step, the bottom rows of the floor's grey) with a smooth bottom read blocked near too,
  // where every column the sonar shows floor at the bottom of (a boundary beyond the blind range
  // by 0.5 m, or far), at least blind_texture_min_floor_columns of them, is textured there: on a
  // tiled floor a column's bottom rows often lie within one smooth tile (without that check,
  // `default` 45 minutes: false ends all along the west corridor). blind_texture_unknown is off
  // (`--blind-texture-unknown`): it kept two more of corridor-2's "close to a wall" starts off the
  // wall but its false blocks cut corridor-2's seeded starts' coverage from 0.82 to 0.73 (session
  // 18). 0 turns it all off (`squint explore --blind-texture 0`); 0.35 since session 18.
  double blind_texture_ratio = 0.35;
  double blind_texture_min_floor = 2.0;
  double blind_texture_hold_s = 10.0;
  // The floor's reference is not taken from a frame whose 90th percentile is itself below
  // blind_texture_ratio x the reference held (within blind_texture_hold_s): a door of plain paint
  // filling the view up close, no floor below it, became its own "floor" and nothing in it read
  // smooth, so the blind view let the robot on into the door (corridor-6, start 4 of seed 12).
  // On since session 20; off: `squint explore --no-blind-texture-keep-ref`.
  bool blind_texture_keep_ref = true;
  // ...judged against the largest reference taken within blind_texture_hold_s, not the latest:
  // turning toward a door up close, each frame a little smoother than the one before, walked the
  // reference down from the tiles' 39 grey levels to the door's own 2.7 within three seconds, one
  // step inside blind_texture_ratio at a time, and the door's columns read unknown (corridor-0,
  // start 2 of seed 8). On since session 22; off: `squint explore --no-blind-texture-keep-peak`.
  bool blind_texture_keep_peak = true;
  bool blind_texture_unknown = false;
  // blind_texture_unknown's rule, applied only until the robot has driven this far (metres of
  // wheel travel) since its start: a robot started close to a wall of the floor's grey has no
  // earlier view of the wall, and no false end there costs coverage (corridor-2, start 2 of seeds 6
  // and 7). The rule is spent at the first stall (the robot has stopped short of the wall, or the
  // rule has held it on open floor: corridor-2, start 4 of seed 2, which dithered for a minute at
  // its start and then set off 30 degrees off the axis). 0: off (`squint explore
  // --blind-texture-start 0`); 2.0 since session 19.
  double blind_texture_start_m = 2.0;
  int blind_texture_min_floor_columns = 8;
  // A blind view whose sonar frame shows periodic horizontal lines in at least this fraction of
  // its column bands (Percept::sonar_wall_lines: a brick wall's mortar, which keeps the glance
  // entropy at corridor level) reads as a wall whatever its entropy, while following (turning in
  // place keeps the entropy rule). 0 turns it off.
  double blind_view_max_wall_lines = 0.375;
  // Side branches met while following (a T met from its bar), from the sonar's memory: a side
  // wall seen abeam (within side_window_m along the axis, side_wall_max_lateral_m across) over
  // branch_wall_before_m of travel, then no wall abeam, is an opening; its far edge is the
  // nearest remembered point ahead on that side. The robot stops at the opening's centre when
  // it is at least branch_min_width_m wide and free for branch_depth_m across (else a door
  // recess), records a junction node, probes the sides and lets the topological map choose.
  // Junctions whose side branch is already known are passed without stopping.
  bool detect_branches = true;
  double side_window_m = 0.3;
  double side_wall_max_lateral_m = 1.8;
  // A side's wall abeam is its nearest point with another remembered point within
  // side_wall_cluster_m of it, not one isolated point: a single point 0.25 m inside the wall of
  // `default`'s east corridor moved the right wall's line inward, the real wall then read beyond
  // the line, and the robot stopped for an "opening on the right" 2 m before the north-east L and
  // turned there (session 23). 0: the nearest point (`squint explore --side-wall-cluster 0`).
  double side_wall_cluster_m = 0.15;
  // Forward travel stops where the disc, moved this far (metres) along its heading, would cover a
  // cell beside its path (at least guard_unknown_inner_m to the side) never known free: floor not
  // seen there, no column's floor showing across it from the bottom row, the disc never on it.
  // The camera sees nothing within 0.6 m, nor beside the robot: a box or a column that left the
  // view in the near blind zone while the robot turned was met with the disc's flank. 0: off, the
  // default. It does not catch those flank contacts: on the three obstacle-course starts it seemed
  // to fix (session 24) it never fires after the first 0.5 m of travel (with guard_unknown_after_m
  // 0.5 the runs are the defaults': the cells beside the path were marked known free); its stops
  // at the start delayed the set-off, and the route that followed missed the obstacles. A robot started
  // near a wall, whose blind zone is never seen free, stands still: the seeded starts' coverage
  // fell from 0.776 to 0.739 on seeds 1-8 (`squint explore --guard-unknown`; sessions 24 and 25).
  double guard_unknown_step_m = 0.0;
  double guard_unknown_inner_m = 0.12;
  // ...and only once the wheels have travelled this far (metres) since the start (0: from the
  // start; `squint explore --guard-unknown-after`).
  double guard_unknown_after_m = 0.0;
  // An armed side's opening ends (its far edge) only at remembered points within
  // branch_line_tolerance_m beyond that side's wall line: the wall resuming, the branch's far
  // corner or an end wall all reach the line, a cluster inside the branch does not (`default`, the
  // 45-minute run of seed 12: points 0.6 m inside the south stem made its mouth 1.16 m wide, a door
  // recess). Off, the default: any point ahead on that side, but the floor-edge band (session 24:
  // on, seed 12 covers 0.999, but seeds 5, 8 and 11 of 16 miss the middle corridor on routes
  // that part at the first junction; `squint explore --far-edge-on-line`).
  bool far_edge_on_line = false;
  // > 0: a remembered point more than branch_line_tolerance_m beyond an armed side's wall line,
  // last seen from farther than this (metres), neither ends that side's opening (its far edge)
  // nor blocks the opening's free-across test: seen through a mouth from afar, a branch's far
  // wall's base is ranged up to a row short (0.5 m at 4 m) and lies inside the branch. `default`'s
  // south stem, 45-minute seeds 11 and 16: its far wall seen from 3.5-5.7 m put points 0.6-0.75 m
  // beyond the line, the mouth read 1.14 m wide, a door recess, and the stem was never entered;
  // with far_edge_on_line the same points failed the free-across test on seed 8 (docs/explore.md,
  // session 38). 0: off, the default (`squint explore --branch-coarse-from`).
  double branch_coarse_from_m = 0.0;
  double branch_wall_before_m = 0.6;
  double branch_wall_gap_m = 0.3;        // shorter breaks in the wall do not end a wall run...
  // ...unless the break was handled as an opening (a door recess rejected as too narrow, a
  // junction): the wall after it starts a new run. Without it a short break consumed the run, and
  // the next side branch along the same wall was passed unseen (`default`'s stem, seed 12 with
  // --wall-lines). On by default since session 17, with the walls' lines; with the glance's heading
  // alone the flaky wall readings of `default`'s carpeted middle corridor give more false openings
  // (collisions on 45-minute seeds 10 and 16; `squint explore --no-rearm-after-gap`;
  // docs/explore.md, sessions 16 and 17).
  bool rearm_after_gap = true;
  double branch_min_width_m = 1.2;
  double branch_default_width_m = 2.0;   // when the far edge is not seen (yet)
  double branch_max_width_m = 4.0;       // a longer gap is not treated as one side branch
  double branch_depth_m = 2.0;
  double branch_max_heading_deg = 15.0;  // no stop while heading farther than this off the axis
  double branch_known_radius_m = 0.8;    // a known junction is used only this close to its node
  // An opening found farther than branch_known_radius_m from a known junction (within the map's
  // merge radius) whose side there was judged a wall is looked at as a new opening instead of
  // being left alone. A false stop 2 m before `default`'s carpeted middle corridor (its side a
  // wall) otherwise hid the real mouth on every later pass (45-minute seed 27). Off by default
  // (`squint explore --opening-beside-wall-node`; docs/explore.md, session 17).
  bool opening_beside_wall_node = false;
  // The wall line of an armed side (the median of the run's last branch_line_samples abeam
  // readings, in the corridor frame): a reading more than branch_line_tolerance_m beyond it is
  // not that wall (a floor-material edge seen through an opening, which the sonar reads about
  // 0.2 m beyond the wall line: `default`'s carpeted middle corridor), so it neither continues the
  // run nor closes the opening's far edge, and the free-across test ignores what lies from
  // branch_line_tolerance_m to branch_line_band_m beyond the line; once the robot turns into such
  // an opening, that band is cleared from the memory until it has crossed it. 0 turns it off
  // (`squint explore --no-floor-edge-openings`); 0.12 since session 12 (an option since session 11;
  // docs/explore.md).
  double branch_line_tolerance_m = 0.12;
  double branch_line_band_m = 0.6;
  int branch_line_samples = 15;
  // The wall line's samples at least this far apart in travel along the corridor (0: one per
  // step, as before). One per step, the 15 samples span the last 0.3 m at full speed, and a pair of
  // points 0.3 m inside a brick wall, abeam for 0.6 m, became the line: the wall beyond them then
  // lay "beyond the line", its run ended 0.64 m before the mouth of `default`'s carpeted middle
  // corridor, and the robot stopped 0.15 m past the mouth's near corner, 1.05 m off its centre line
  // (45-minute seed 1 with --wall-line-align --reopen-blocked-driven). 0.1 spans 1.5 m. Off (0) by
  // default (`squint explore --branch-line-spacing 0.1`; docs/explore.md, session 41).
  double branch_line_spacing_m = 0.0;
  // The band cleared is only as long as the opening (from where that side's wall run ended, for
  // the opening's width), not centred on where the robot stopped: stopped 1 m short of a T's
  // bar's centre line (corridor-9 start 5 of seed 3), the band reached back over the last 1.8 m
  // of the corridor's own wall, whose base the sonar read inside it, cleared the wall's end from
  // the memory, and the robot turned into the branch and met the corner it could no longer see
  // (session 23). Off: the band spans the stop ± (half the width + side_window_m), as before.
  bool floor_edge_band_mouth = true;
  // Mouth centring: before turning into a side branch the robot moves along the corridor to the
  // branch's centre line. The branch's two walls are the remembered points from 0.25 m to
  // mouth_band_m beyond the corridor's own wall line on that side (the last abeam wall distance
  // there): the mouth is the gap between two of their clusters (at least 2 points within 0.3 m
  // each), 1.2-4 m wide (branch_min_width_m .. branch_max_width_m), whose centre lies nearest the
  // robot. A stop that is early by a metre (the far edge seen early, a false opening just before
  // an L corner) otherwise turns the robot into the branch along its wall. The robot turns back to
  // the axis and drives (forward, or backward up to mouth_back_max_m) when that centre is at least
  // mouth_centre_min_m and at most mouth_centre_max_m away. 0 turns it off (`squint explore
  // --no-mouth-centring`); 0.25 since session 12 (docs/explore.md).
  double mouth_centre_min_m = 0.25;
  double mouth_centre_max_m = 1.5;
  double mouth_back_max_m = 0.8;
  double mouth_band_m = 1.5;
  double mouth_speed_mps = 0.25;
  // Mouth centring from the corridor's wall line as it stands now: the last abeam wall distance on
  // that side is moved by the robot's sideways travel since it was read (a corner rounded off the
  // axis before the stop moves the robot toward that wall), and the band starts 0.2 m inside the
  // wall line, so the remembered points of the corridor's own wall bound the mouth too: a gap
  // along which the wall still stands is no mouth (a wall run that ended early, its synthetic
  // corner metres before the real one, otherwise sends the robot back into the wall's end).
  // On by default (`squint explore --no-mouth-wall-line`; docs/explore.md, session 17).
  bool mouth_wall_line = true;
  // Mouth centring leaves out a remembered point with no other within the clusters' 0.3 m along
  // the axis: one stray point inside a mouth splits it into two gaps, neither with a wall of two
  // points on both sides, and no centre is found (corridor-8's cross, starts 8 of seed 95 and 3 of
  // seed 108: a point 0.1 m past the near corner, the robot turned into the branch from 1 m off its
  // centre line and met the corner). On by default since session 39 (`squint explore
  // --no-mouth-drop-strays`; docs/explore.md, sessions 37 and 39).
  bool mouth_drop_strays = true;
  // A stop's node marks the branch the robot came in by as explored only when it came along it:
  // it departed from a node, or it has driven at least this far since it set off (a robot that
  // starts in a junction has not driven the corridor behind it, which may be a wall). 0 marks it
  // always (`squint explore --arrival-min-travel 0`); 1.0 since session 18 (docs/explore.md).
  double arrival_min_travel_m = 1.0;
  // The drive to a mouth's centre ends where the wheels made no progress for this long (a wall
  // the sonar cannot see from up close), and the robot turns from there. 0: only the drive's time
  // limit ends it (`squint explore --shift-stall 0`); 0.3 since session 18 (docs/explore.md).
  double shift_stall_s = 0.3;
  // The drive forward to a mouth's centre takes the latest scan's blocked-near columns as
  // following does after trust_memory_after_m (only the narrow sector, and not where the floor was
  // seen from farther back) when the robot came that far along the corridor: it saw the floor
  // ahead on its way in, and a tiled floor's joints read blocked near there held the drive for its
  // whole time limit, so the robot turned into the branch a metre short of its centre and met the
  // corner (corridor-8, start 4 of seed 5). On since session 19 (`squint explore --no-shift-trusts-memory`).
  bool shift_trusts_memory = true;
  // > 0 (metres): on that drive (with the same conditions: after trust_memory_after_m in the
  // corridor, within 45 degrees of the axis), where the remembered points leave less free travel
  // than this, that free travel is the guard's, not the latest scans': a wall filling the view
  // within the blind range blocks the drive whatever the floor seen before said, but the robot
  // ranged that wall's base on its way in. At corridor-1's T (1.6 m wide) the robot stopped 1.3 m
  // from the cross corridor's far wall, the drive of 0.46 m to its centre line was held for its whole
  // time limit (the points left 0.85 m), and the robot turned 0.5 m off the centre line, steered
  // clear of the mouth's corner, stalled, took the cross corridor for a dead end and met that
  // corner (start 9 of seed 94). `squint explore --shift-trusts-points M`; docs/explore.md,
  // sessions 43 and 45. 1.2 since session 45 (0: off).
  double shift_points_within_m = 1.2;
  // trust_memory_max_wall_lines takes the largest wall-line fraction of the sonar frames over the
  // last wall_lines_hold_s seconds, not the latest frame's alone: approaching a brick wall's corner
  // the lines come and go from frame to frame as the brick leaves the view (corridor-9, start 9 of
  // seed 14). 0: the latest frame only (`squint explore --wall-lines-hold 0`); 1.0 since session 19.
  double wall_lines_hold_s = 1.0;
  // The explorer's memory: ObstacleMemoryOptions' defaults, but for own-range clearing for driving
  // only (clear_own_within_m 1.2 with clear_own_driving_only; since session 49, `squint explore
  // --no-own-range-driving` turns it off; docs/explore.md, sessions 48 and 49). A chair leg the
  // sonar's median votes out stays remembered for the disc's free travel.
  ObstacleMemoryOptions memory = ExplorerMemoryDefaults();
  TopoMapOptions map;

  std::string Validate() const;
};

enum class ExploreState {
  kScan,     // start-up full turn, looking for the corridor
  kFollow,   // driving down the corridor
  kProbe,    // stopped at the end: rotating to look left and right
  kTurn,     // rotating to the chosen branch
  kBackOff,  // stalled against something: reversing a little
  kAlign,    // standing still, rotating until the fused heading reads zero (after the scan)
};
const char* StateName(ExploreState s);

// Something that happened, for logs and maps (positions are odometry poses).
struct ExploreEvent {
  enum class Kind { kScanDone, kEndDetected, kTurn, kStall, kJunction };
  Kind kind = Kind::kTurn;
  double stamp_s = 0.0;
  Pose2 odom_T_robot;
  int turn_deg = 0;   // for kTurn: +90 left, −90 right, 180 around, 0 straight on
  int node = -1;      // topological node, when known
  std::string note;   // e.g. "left open, right wall"
};

// The side-branch detector's state for one side while following (travel coordinates are metres
// driven in the current corridor).
struct SideTrack {
  double wall_first_m = -1.0;  // start of the current run of wall seen abeam (< 0: none)
  double wall_last_m = -1.0;   // where the wall was last seen abeam
  bool armed = false;          // a wall run long enough was seen: a gap after it is an opening
  bool consumed = false;       // this gap was handled (junction recorded, passed or rejected)
  double far_m = -1.0;         // the opening's far edge (travel coordinate), when seen
  Eigen::Vector2d ref{0.0, 0.0};   // the run's first robot position (odometry frame)
  std::vector<double> line;        // the run's last abeam readings as outward offsets from ref
  double line_last_m = -1e9;       // travel at the last of them (branch_line_spacing_m)
};

// Whether a wall seen abeam at travel `travel_m` starts a new run of `track` (the first, one after a
// break longer than branch_wall_gap_m, or with rearm_after_gap one after a break already handled
// as an opening) instead of continuing it.
bool StartsNewWallRun(const SideTrack& track, double travel_m, const ExplorerOptions& options);
// Mouth centring's gap: `along` holds where the remembered points of a side branch's walls (and
// the near corner where that side's wall run ended) lie along the axis from the robot. The mouth
// is the gap between two clusters (at least 2 points within 0.3 m each), branch_min_width_m to
// branch_max_width_m wide, whose centre lies nearest the robot; with mouth_drop_strays points with
// no other within 0.3 m are left out first. Its centre, or none where there is no such gap within
// mouth_centre_max_m.
std::optional<double> MouthGapCentre(std::vector<double> along, const ExplorerOptions& options);

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
  // True once after every new corridor starts and after every axis re-acquisition: the caller
  // restarts the Perceiver's heading filter (its state is relative to the previous axis).
  // prior_deg (when given) is then the heading the axis implies (degrees; NaN: none, start from
  // the next frame; heading_filter_prior_std_deg).
  // The robot's confirmed lateral position from the ceiling lights' line (metres, left positive)
  // at time stamp_s and odometry pose odom_T_robot; false when none (light_centre_gain).
  bool LightLateral(double stamp_s, const Pose2& odom_T_robot, double* lateral_m) const;
  bool TakeHeadingFilterReset(double* prior_deg = nullptr);
  // True while the explorer turns or stands in place and needs every frame fully processed (scan, alignment):
  // the caller then resets the gate's reference before the frame (a still view never passes).
  bool WantsFullProcessing() const { return state_ == ExploreState::kAlign || state_ == ExploreState::kScan; }
  // Vision-corrected dead reckoning (odometry translation, yaw drift removed by the corridor
  // axis estimates), in the map frame whose direction 0 is the first corridor's axis.
  const Pose2& MapPose() const { return map_pose_; }
  const TopoMap& Map() const { return map_; }
  const std::vector<ExploreEvent>& Events() const { return events_; }
  int Turns() const { return turns_; }
  // The visual sonar's memory (odometry frame), for drawing and tests.
  const ObstacleMemory& Memory() const { return memory_; }
  // Times the sonar safety layer lowered a forward command (for logs).
  long SpeedLimited() const { return speed_limited_; }
  int EndsDetected() const { return ends_; }
  // Side openings met while following and recorded as junctions (stopped at or passed).
  int JunctionsDetected() const { return junctions_; }
  // Frames on which the obstacle override steered (or stopped) the robot, and its stop-and-turns.
  long ObstacleOverrides() const { return avoid_overrides_; }
  int ObstacleStops() const { return avoid_stops_; }
  // Sonar scans whose blocked-near view was read as unknown (blind_view_entropy_ratio).
  long BlindViews() const { return blind_views_; }
  // Sonar columns read blocked near from the walls' lines' frame's smooth bottom (blind_texture_ratio).
  long BlindTextureColumns() const { return blind_texture_kept_; }
  // Sonar scans that showed the robot's own reflection (mirror_watch).
  int MirrorsFound() const { return mirror_.Found(); }
  // How often the walls' lines overrode the glance at a standstill under wall_line_align_over_deg
  // (scan axes and alignment medians replaced); 0 means the run is the run without it step for step.
  int AlignLineOverrides() const { return align_line_overrides_; }
  // Scans whose choice of direction scan_wall_entropy changed (0: the run without it step for step).
  int ScanWallEntropySkips() const { return scan_wall_entropy_skips_; }
  // Scans whose choice of direction scan_entropy_floor changed (the best-scoring direction was
  // skipped); 0 means the run is the run without it step for step.
  int ScanEntropySkips() const { return scan_entropy_skips_; }
  int WallKeepFrames() const { return wall_keep_frames_; }
  // True while the walls' lines are wanted at a standstill (wall_line_align or wall_line_align_over_deg).
  bool WantsAlignLines() const { return opt_.wall_line_align || opt_.wall_line_align_over_deg > 0.0; }
  // Vertical edges ranged inside the blind range while setting off (setoff_near_edges).
  long NearEdgesRanged() const { return near_edges_ranged_; }
  // Contacts felt from the wheels (feel_contacts).
  int ContactsFelt() const { return contacts_felt_; }

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
  // feel_contacts: true when the wheels show a contact this step (then backing off).
  bool FeelContact(const Percept& p, const Pose2& moved);
  Command AlignStep(const Percept& p);
  // Rotates toward target; returns true when there and settled.
  bool Rotate(const Percept& p, Rotation& r, Command& cmd) const;
  void UpdateAxis(const Percept& p);
  // `delta`: the odometry motion since the previous step (Between(last_odom_, p.odom_T_robot)).
  void UpdateMapPose(const Percept& p, const Pose2& delta);
  void StartFollow(const Percept& p);
  void StartTurnTo(const Percept& p, int dir, int turn_deg, const std::string& note);
  void Decide(const Percept& p);
  // Side branches while following: updates the two side tracks from the sonar memory; returns
  // true when the robot stopped at a junction (state changed to kProbe).
  bool TrackSides(const Percept& p);
  bool NearKnownEnd() const;  // known_end_slow_m
  bool OnOpening(const Percept& p, int side, double width_m);
  // The side branch's centre line along the axis from the robot (metres, ahead positive), from the
  // remembered walls of its mouth (mouth_centre_min_m); false when they do not show one.
  bool MouthCentre(const Percept& p, int side, double* along_m) const;
  void StartScan(const Percept& p);  // a full turn in place from the current yaw, its tallies cleared
  // At a standstill, whether the walls' lines, disagree_deg from the glance's axis (90 where the
  // glance gives none), replace it: always with wall_line_align; with wall_line_align_over_deg
  // where they disagree by more than that (counted in align_line_overrides_).
  bool LinesOverride(double disagree_deg);
  void ClearAlignSamples();          // the glance's and the walls' lines' headings gathered while aligning
  // Before a turn into a side branch: back to the axis, then along it to the mouth's centre.
  Command ShiftStep(const Percept& p);
  void StartProbe(bool at_end = false);  // at_end: started by the end of a corridor (end_probe_memory)
  double ReferenceEntropy() const;
  // The remembered walls' axis modulo 90 degrees (odometry frame), when axis_from_walls is on and
  // the memory holds enough of them.
  bool WallAxis(double* axis_mod90) const;
  // Turns the corridor axis and the map's yaw offset together (a drifted axis pulled back to the
  // remembered walls').
  void RotateAxis(double by_rad);
  void Emit(ExploreEvent::Kind kind, const Percept& p, int turn_deg, const std::string& note);
  // Sonar: memory update, and the last word on every command (speed limit).
  void UpdateSonar(const Percept& p);
  Command Guard(const Percept& p, Command cmd);
  // Whether the latest scan's blocked-near columns count in full along odometry yaw `yaw`
  // (false: the narrow sector; see trust_memory_after_m).
  bool UseBlocked(double yaw) const;
  // On the drive forward to a mouth's centre, after trust_memory_after_m in the corridor (the
  // condition shift_trusts_memory and shift_points_within_m share).
  bool ShiftingAfterTravel() const;
  // The disc's free travel along odometry yaw `yaw` (ObstacleMemory::FreeTravel). `judging`: for
  // a judgement of walls and openings (an end, a side's probe, a branch's depth), not for driving:
  // the edges' soft points kept past blind_points_keep_s are left out
  // (ObstacleMemoryOptions::blind_points_edge_keep_driving_only).
  double Free(const Percept& p, double yaw, double max_m, bool judging = false) const;
  // Best heading (odometry yaw) near `desired_yaw` by free travel; its free travel in *free.
  // `left_m` / `right_m` (> 0): side walls at those lateral distances from the robot run along
  // the axis (gap_side_wall_max_m); a candidate's free travel ends where the disc would reach them.
  double BestGap(const Percept& p, double desired_yaw, double* free, double left_m = -1.0, double right_m = -1.0) const;
  // Travel along odometry yaw `yaw` until the disc (with safety_margin_m) reaches the line of a
  // side wall at `left_m` / `right_m` (> 0) from the robot, running along the axis; infinity when
  // `yaw` does not lead toward such a wall or its centre would not reach the line within
  // lookahead_m + robot_radius_m.
  // Free travel across toward an opening's side, ignoring the band beyond its wall line
  // (line_m: the line's distance from the robot, < 0: none, the plain Free).
  double FreeAcross(const Percept& p, double side_yaw, double line_m) const;
  void ClearFloorEdgeBand(const Percept& p);
  // Where a side's last wall run ended, along the axis from the robot (negative: behind it).
  double WallRunEndAlong(int side) const;
  // The unit vector to the left of the corridor axis (odometry frame).
  Eigen::Vector2d AxisLeft() const;
  double SideLineTravel(double yaw, double left_m, double right_m) const;

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
  // The light line's recent readings as offsets across the corridor from light_ref_ (odometry
  // frame, left of the axis positive), and the last time they were confirmed.
  struct LightReading {
    double stamp_s = 0.0;
    double across_m = 0.0;
  };
  std::vector<LightReading> light_readings_;
  struct LightDrift {
    Eigen::Vector2d odom;  // where the reading was taken (odometry frame)
    double lateral_m;      // the robot's offset from the lights' line, left positive
  };
  std::vector<LightDrift> light_drift_;
  void UpdateLightDrift(const Percept& p);
  Eigen::Vector2d light_ref_ = Eigen::Vector2d::Zero();
  double light_across_m_ = 0.0;
  double light_confirmed_s_ = -1.0;
  double light_axis_s_ = -1.0;  // when the lights' line last moved the axis (light_axis_gain)
  // The walls' lines' recent axes (odometry frame) and when they last moved the axis.
  struct WallLineReading {
    double stamp_s = 0.0;
    double axis_rad = 0.0;
  };
  std::vector<WallLineReading> wall_line_readings_;
  // The latest wall lines with their place (wall_keep_m): the odometry pose they were read from,
  // the lines' direction in that robot frame, and their offsets (one or two).
  struct WallKeepReading {
    double stamp_s = -1.0;
    Pose2 odom_T_robot;
    double direction_rad = 0.0;
    double offsets_m[2] = {0.0, 0.0};
    int lines = 0;
  };
  WallKeepReading wall_keep_reading_;
  int wall_keep_frames_ = 0;  // following frames whose heading the rule bounded
  bool WallKeep(const Percept& p, double* target_rel_axis);
  double wall_line_axis_s_ = -1.0;
  struct WallLineAhead {
    double stamp_s, yaw, ahead_m;  // Percept::wall_line_corridor_ahead_m (0: none, or off the axis) and where it was taken
  };
  std::vector<WallLineAhead> wall_line_ahead_;  // the last readings, within kWallLineAheadHoldS
  // The axis a walls' lines reading implies (odometry yaw − its heading), modulo 90° the one
  // nearest the axis held, less that axis; none without a reading or beyond wall_line_gate_deg.
  std::optional<double> WallLineAxisDiff(const Percept& p) const;
  void NoteWallLinesAhead(const Percept& p);
  bool WallLinesFree(const Percept& p, double yaw) const;
  // The walls' lines' frame's bottom texture per column when blind_texture_ratio applies (it
  // updates the floor's reference), else null.
  const std::vector<float>* BlindTexture(const Percept& p);
  // Whether the robot came along the corridor it is in (ExplorerOptions::arrival_min_travel_m).
  bool CameAlong() const {
    return opt_.arrival_min_travel_m <= 0.0 || travel_in_corridor_m_ >= opt_.arrival_min_travel_m;
  }
  void UpdateWallLines(const Percept& p);
  bool WallLinesHold(double stamp_s) const;
  bool probe_at_end_ = false;  // the probe under way was started by the end of a corridor (StartProbe)
  void UpdateLight(const Percept& p);

  // Follow.
  double dist_end_m_ = -1.0;
  int end_count_ = 0;
  int entropy_low_count_ = 0;
  double travel_in_corridor_m_ = 0.0;
  double odometer_m_ = 0.0;  // wheel travel since the start (UpdateMapPose)
  bool stalled_since_start_ = false;  // the follow state's stall guard has fired (blind_texture_start_m)
  // Where and when the last view judged a wall by its entropy was taken (wall_view_hold_m).
  double wall_view_odometer_m_ = -1.0;
  double wall_view_yaw_ = 0.0;
  double wall_view_s_ = 0.0;
  std::vector<double> ref_entropy_;  // ring buffer of glance entropies while following
  int ref_next_ = 0;
  double last_ref_entropy_ = 0.0;
  bool gate_reset_ = true;
  bool heading_filter_reset_ = true;
  bool heading_filter_prior_ = false;  // the reset may start from the axis' heading
  // Wheel progress over windows of time (odometry only): a window starts, and once it has lasted
  // window_s ends, telling whether the robot moved less than min_m in it (and the next starts).
  struct ProgressWindow {
    double since_s = -1.0;  // < 0: none started
    Eigen::Vector2d at = Eigen::Vector2d::Zero();
    void Reset() { since_s = -1.0; }
    // `start_s`: the stamp a window started now is counted from (default now_s).
    bool Stalled(double now_s, const Eigen::Vector2d& position, double window_s, double min_m, double start_s = -1.0) {
      if (since_s < 0.0) {
        since_s = start_s >= 0.0 ? start_s : now_s;
        at = position;
        return false;
      }
      if (now_s - since_s < window_s) return false;
      const double moved = (position - at).norm();
      since_s = now_s;
      at = position;
      return moved < min_m;
    }
  };
  // Stall guard while following.
  ProgressWindow stall_;
  double backoff_until_s_ = 0.0;
  // After a felt contact: reverse this far (metres) from backoff_from_ (< 0: by time only).
  Eigen::Vector2d backoff_from_ = Eigen::Vector2d::Zero();
  double backoff_reverse_m_ = -1.0;

  // Scan.
  std::vector<double> scan_axis_mod90_;  // candidate axis angles (rad, [0, pi/2)) from the scan
  std::vector<double> scan_line_axis_mod90_;  // the same from the walls' lines (wall_line_align)
  std::vector<double> outlier_axes_;
  std::vector<double> dist_hist_;
  std::vector<double> scan_sum_;
  std::vector<int> scan_count_;
  std::vector<int> scan_views_;       // per bin: sonar views during the scan
  std::vector<int> scan_wall_views_;  // ...of them read as a wall filling the view
  double scan_turned_ = 0.0;
  double scan_start_yaw_ = 0.0;
  double scan_prev_yaw_ = 0.0;
  bool scan_rotating_ = true;
  Rotation scan_final_;
  std::vector<double> align_samples_;
  std::vector<double> align_line_samples_;  // the walls' lines' headings while aligning (wall_line_align)
  bool align_line_scanned_ = false;  // the lines sent this alignment to a full scan once already
  int align_line_overrides_ = 0;  // (wall_line_align_over_deg) the lines overrode the glance
  int scan_wall_entropy_skips_ = 0;  // (scan_wall_entropy) scans whose choice it changed
  int scan_entropy_skips_ = 0;    // (scan_entropy_floor) scans whose choice it changed
  static constexpr double kAlignLineAgreeDeg = 20.0;  // the lines' heading this far from the glance's: scan
  int align_round_ = 0;
  bool align_rotating_ = false;
  bool start_checked_ = false;
  double start_entropy_sum_ = 0.0;
  int start_entropy_n_ = 0;
  Rotation align_rot_;

  // Probe and turn.
  int node_ = -1;
  int probe_phase_ = 0;  // 0 left, 1 right
  Rotation rot_;
  int look_count_ = 0;
  double look_sum_ = 0.0;
  double side_entropy_[2] = {0.0, 0.0};
  double side_free_m_[2] = {-1.0, -1.0};  // sonar free travel seen when probing each side
  int gap_side_dir_ = -1;  // map direction of the opening that made this stop (junctions only)
  int gap_other_dir_ = -1;  // the other side's, at a crossing found past a floor edge
  // The band beyond an opening's wall line (a floor edge seen through it), in the frame of the
  // robot at the stop facing that side (map direction dir): cleared from the memory when the robot
  // turns into it.
  // s: toward the side, from the stop; l: to the left of that direction (along the corridor's
  // axis backward for a left side, forward for a right one).
  struct FloorEdgeBand {
    int dir = -1;
    Pose2 frame;
    double s0 = 0.0, s1 = 0.0, l0 = 0.0, l1 = 0.0;
  };
  std::optional<FloorEdgeBand> floor_edge_candidates_[2];  // recorded at the stop, per side (left, right)
  std::optional<FloorEdgeBand> floor_edge_band_;  // turned into: cleared on every scan until crossed
  int probe_sides_[2] = {1, 3};  // relative turns (in quarter turns) to probe
  int n_probes_ = 0;
  std::vector<int> dead_end_reprobes_;  // per node: arrivals whose dead-end sides were looked at again
  int turn_to_dir_ = 0;
  // Mouth centring (mouth_centre_min_m): the shift along the axis still to drive before the turn
  // (0: none), from where, facing which way, and since when.
  double shift_m_ = 0.0;
  Eigen::Vector2d shift_from_ = Eigen::Vector2d::Zero();
  Rotation shift_rot_;
  bool shift_aligned_ = false;
  double shift_start_s_ = 0.0;
  ProgressWindow shift_progress_;      // the drive's wheel progress while the guard lets it drive (shift_stall_s)
  Command last_cmd_;                    // the previous step's command, after the guard
  double last_cmd_s_ = -1.0;            // its stamp
  // Contact feeling (feel_contacts): consecutive steps commanded forward without wheel progress,
  // the odometry distance driven forward along a (nearly) straight path since the robot last
  // turned in place or reversed, and the contacts felt.
  int contact_run_ = 0;
  double forward_run_m_ = 0.0;
  int contacts_felt_ = 0;
  bool last_scan_blind_ = false;        // the latest sonar scan was a blind view read as unknown
  double floor_texture_ref_ = 0.0;      // the floor's bottom texture in the walls' lines' frame (blind_texture_ratio)
  double floor_texture_ref_s_ = -1e9;   // when it was last measured
  // The references taken within blind_texture_hold_s, decreasing (a sliding window's maximum).
  std::deque<std::pair<double, double>> floor_texture_peaks_;
  long blind_texture_kept_ = 0;         // sonar columns read blocked near from the bottom texture
  std::vector<float> texture_sorted_;   // BlindTexture's work buffer
  double last_wall_m_[2] = {-1.0, -1.0};  // the last abeam wall distance per side in this corridor
  Eigen::Vector2d last_wall_at_[2] = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};  // odometry position of that reading

  int turns_ = 0;
  int ends_ = 0;
  int junctions_ = 0;
  SideTrack sides_[2];  // 0 left, 1 right

  // Visual sonar.
  ObstacleMemory memory_;
  MirrorWatch mirror_;
  NearEdgeRanger near_edge_ranger_;
  std::vector<double> edge_bearings_;
  long near_edges_ranged_ = 0;
  std::vector<SonarColumn> sonar_copy_;  // a scan with blocked-near columns read as unknown (blind view)
  long blind_views_ = 0;
  bool view_is_wall_ = false;  // this step's sonar view read as a wall filling the view
  bool sonar_seen_ = false;
  double last_scan_yaw_ = 0.0;
  double last_wall_lines_ = 0.0;  // the latest scan's Percept::sonar_wall_lines (over wall_lines_hold_s)
  std::deque<std::pair<double, double>> wall_lines_recent_;  // (stamp, fraction) within wall_lines_hold_s
  long speed_limited_ = 0;
  bool rescan_ = false;  // the scan under way is a recovery (keeps the map frame)
  bool setting_off_ = true;  // from a start or scan to trust_memory_after_m of following or a turn

  // Obstacle override: the latest advice, when and at which odometry yaw it was taken.
  // Returns true (and the command) when the advice overrides corridor following.
  bool ObstacleOverride(const Percept& p, Command* cmd);
  ObstacleAdvice avoid_advice_;
  double avoid_stamp_s_ = -1.0;
  double avoid_yaw_ = 0.0;
  int avoid_blocked_count_ = 0;
  int avoid_in_path_count_ = 0;
  long avoid_overrides_ = 0;
  int avoid_stops_ = 0;
};

}  // namespace squint::explore
