// Every tunable of corridor perception, with its documented default (the member initialisers
// below are the only defaults; the CLI and YAML files fill these structs).
#pragma once

#include <array>
#include <string>

#include "squint/corridor/glance.hpp"
#include "squint/corridor/measure.hpp"

namespace squint::corridor {

// One heading cue: its fusion weight and its linear calibration
// heading_deg = scale * camera_heading_deg + bias_deg (identity by default).
struct HeadingCueOptions {
  bool enabled = true;
  double weight = 1.0;
  double scale = 1.0;
  double bias_deg = 0.0;
  // Standard deviation of the cue's calibrated error (degrees): its measurement noise in the
  // heading filter (HeadingFilterOptions). `squint calibrate` writes the fitted σ.
  double std_deg = 8.0;
};

// A filter over time for the fused heading (the Kalman filter, heading half): the state
// is rotated by the odometry's turn between frames (process noise process_std_deg_per_sqrt_s ·
// sqrt(dt) + odom_noise_fraction · |turn| per frame, process_std_deg per frame in place of the
// first term when the frame interval is unknown, no_odom_std_deg per frame without a turn
// reading) and updated on every processed frame by each cue's calibrated estimate with the cue's
// std_deg. The noise is per second, not per frame, so the filter's memory is the same at 4 Hz
// and at 30 Hz: 0.1 deg/sqrt(s) was chosen on the calibration sets (orient-1-00/01 and
// orient-4-00/01, the simulator's corridor-0…4 sweeps and drives; docs/calibration.md).
// An estimate more than sqrt(gate_chi2) σ from the prediction is rejected; after
// reinit_after_rejections consecutive rejections the state restarts from the next estimate.
// Off by default (the heading is the per-frame fusion below); `squint calibrate` turns it on
// in the file it writes (docs/calibration.md compares both).
struct HeadingFilterOptions {
  bool enabled = false;
  double process_std_deg_per_sqrt_s = 0.1;
  double process_std_deg = 0.3;
  double odom_noise_fraction = 0.05;
  double no_odom_std_deg = 3.0;
  double gate_chi2 = 9.0;
  int reinit_after_rejections = 20;

  std::string Validate() const;
};

struct HeadingOptions {
  // Per cue, indexed by HeadingCue. The paper (§5.1) found bright pixels and entropy most
  // accurate on its corridors; on the ray-traced dev corridors (../shared/data/orient-*), the
  // drives and the simulator's sweeps, symmetry and the phase line vote are (per-cue RMSE /
  // median error on orient-*: symmetry 10.8 / 1.6 deg, phase 7.2 / 2.1, bright 12.2 / 5.5,
  // vanishing 13.7 / 5.9), hence these weights. A cue with weight 0 is not computed:
  // - entropy: on orient-* its sign is wrong on 59% of the frames with |heading| >= 5 deg (it
  //   peaks on the textured near wall); give it a weight (paper: the best cue) on corridors
  //   with plain walls and a lit far end;
  // - vanishing (self-similarity): the least accurate cue on orient-*, the drives and the
  //   simulator's sweeps, and any weight > 0 raises the fused error on all three (the phase line
  //   vote finds the same vanishing point more reliably at 32×24); it is also half the glance's
  //   time. Bright pixels keep a small weight: the ceiling lights help on orient-* and drive-*.
  std::array<HeadingCueOptions, kHeadingCueCount> cues = {{
      {.weight = 0.0},   // entropy: inverted on the dev data (see above)
      {.weight = 2.0},   // symmetry
      {.weight = 2.0},   // phase (line vote)
      {.weight = 0.0},   // vanishing (see above)
      {.weight = 0.5},   // bright
  }};
  // Width of the vertical slice around each column for entropy (f1) and phase (f3), pixels.
  int slice_width_px = 3;
  // Columns this close to the glance's left or right edge cannot hold a curve extremum: an
  // argmax there is "peak at border" (the true maximum may lie outside the view).
  int border_px = 1;
  // Minimum prominence of a curve's extremum, (peak - median) / (max - min) of the curve, below
  // which a curve counts as flat.
  double min_prominence = 0.2;
  // Grey levels are quantised to 2^bits bins for column entropy and symmetry histograms.
  int column_bits = 3;
  // Symmetry (f2): largest mirror half-width in columns, and the smallest one at which an axis
  // near the border is still scored.
  int symmetry_half_width_px = 8;
  int symmetry_min_half_width_px = 3;
  // Vanishing point (f4): grey levels quantised to 2^bits bins (3 -> 8 bins, a 64-bin joint
  // histogram). With a known camera only vanishing points within vanishing_row_margin_px glance
  // rows of the horizon row are searched (a corridor's vanishing point lies on the horizon).
  int vanishing_bits = 3;
  double vanishing_row_margin_px = 1.5;
  // Vanishing points farther than this many columns outside the glance are rejected.
  double vanishing_max_outside_px = 4.0;
  // Bright pixels (f5): rows of the upper part used (fraction of the glance height, paper: the
  // upper half), and the minimum separation of the two k-means centres in grey levels.
  double bright_rows_fraction = 0.5;
  double bright_min_separation = 24.0;
  int kmeans_iterations = 10;
  // The bright cluster must hold at most this fraction of the rows' pixels (a lit wall, not lights).
  double bright_max_fraction = 0.5;
  // Symmetry (f2): score each axis by its mutual information times the number of mirrored pairs
  // (relative to the widest window), i.e. by the evidence against "left and right independent"
  // (n·MI is half the G statistic of that test), instead of the per-pair MI of eq. 2. Narrow
  // windows at the glance border hold few pairs, so a near wall's row banding there (ceiling,
  // wall, floor bands mirror onto themselves) no longer outscores the corridor's axis.
  bool symmetry_significance = true;
  // Phase (f3): pixels whose Sobel magnitude (grey levels per pixel) is below this are ignored.
  double phase_min_gradient = 2.0;
  // Phase (f3), how the phases are aggregated. true (default): each edge pixel's phase gives the
  // direction of its edge line; the lines are extended to the horizon row (the camera's, else the
  // middle row) and vote, weighted by gradient magnitude, for the column where they cross it: the
  // corridor's parallel edges all meet at the vanishing point. false: the paper's form, the
  // column where the mean phase of a window changes sign (min |Σ phase|).
  bool phase_line_vote = true;
  // Line vote: edges within this angle of vertical (door frames, wall corners: they do not run
  // down the corridor) and pixels within phase_min_horizon_rows of the horizon row (their lines
  // barely constrain the crossing) do not vote.
  double phase_min_vertical_deg = 20.0;
  double phase_min_horizon_rows = 2.0;
  // Phase balance: near-horizontal edges whose phase |atan(gy/gx)| exceeds this are ignored.
  double phase_max_deg = 75.0;
  // Estimates whose |heading| exceeds this are "out of range".
  double max_abs_heading_deg = 40.0;
  // Fusion of the per-cue curves (default): each cue's score curve, normalised to
  // (curve − median) / (max − min) and resampled onto the glance columns' headings through the
  // cue's calibration, is added with the cue's weight; the fused heading is the maximum of the
  // sum. A cue thus also contributes where its own maximum lost narrowly (a runner-up peak on the
  // corridor's axis, while its maximum sits on a near wall). Cues without a usable curve (uniform
  // frame, no gradient, no bright cluster, no match) do not contribute. false: the consensus of
  // the cues' own estimates below (agreement_deg, min_consensus_cues).
  bool fuse_curves = true;
  // Consensus fusion: the estimates form a consensus when they lie within this many degrees of
  // the weighted median; the others are outliers. The fused heading is the weighted mean of the
  // consensus. With curve fusion, a cue counts as fused when its estimate lies this close to the
  // fused heading.
  double agreement_deg = 6.0;
  // A consensus needs at least this many cues (capped at the number available). With 2 one
  // cue alone, which is wrong far more often than two agreeing ones, never decides; when no two
  // cues agree the fused heading is the weighted mean of all of them. 1 = the heaviest group.
  int min_consensus_cues = 2;
  // Used only when the camera has no intrinsics: heading = deg_per_column * (u - centre).
  double fallback_deg_per_column = 1.75;
  // The filter over time (off by default).
  HeadingFilterOptions filter;

  std::string Validate() const;
};

// Distance to the end from where the end wall stands on the floor (beyond the paper: the obstacle
// paper's floor-contact point, eq. 16, applied to the end of the corridor). Needs the full frame
// (Perceiver::Process) and a camera with intrinsics, height and pitch. In each column within
// ±half_width_deg of the image centre (3 columns averaged), scanning down from the horizon row,
// the first place where the grey level changes by at least min_step between two neighbouring rows
// (refined to the strongest such change in the next 2 rows, sub-pixel by a parabola) is where
// the end wall meets the floor: the end wall fills the view about the horizon, and its base is the
// first edge below it. That row's floor point (CameraModel::FloorPoint) gives the distance along
// the robot's axis; the median over the columns is the frame's reading when at least
// min_column_fraction of them gave one and it lies within [min_m, max_m]. Its temporal median
// (median_frames, moved to the current frame by odometry like time to contact) is
// PerceptionResult::dist_floor_m. Where it has a reading, it is the fused distance
// (overrides_fusion): a floor point at a known camera height is a measurement of geometry, not
// of image change, and on the calibration drives drive-3-00* it is within a few centimetres up to
// 10 m (docs/calibration.md, session 8); elsewhere the three cues' fusion answers.
// The floor contact's motion test keeps at most this many readings (at 30 Hz, 2 m at 0.4 m/s is
// 150 frames).
inline constexpr int kMaxFloorMotionReadings = 512;

struct FloorContactOptions {
  bool enabled = true;
  double half_width_deg = 2.0;
  double min_step = 6.0;
  double min_column_fraction = 0.5;
  double min_m = 0.3;
  double max_m = 20.0;
  bool overrides_fusion = true;
  // The override needs corroboration: the three cues' fused distance must lie within
  // agreement_ratio × itself of the floor contact's (0 = no check; without a fused distance no
  // override). On brick end walls a mortar line below the horizon is taken for the wall's base
  // and the reading is metres too far (drive-3-01*, the simulator's corridor-1 and corridor-9).
  double agreement_ratio = 0.5;
  // The override is also taken where the floor contact corroborates itself under the odometry
  // (motion_window_m > 0; 0 = off, the default; `squint calibrate` writes 2): a floor point
  // stays put in the odometry frame, so the end's position travel + reading of every raw
  // reading within the last motion_window_m of travel is the same. With E the median of those
  // positions, a reading at travel t is an inlier when its row lies within motion_tol_rows of
  // the row the floor point at E − t projects to; at least motion_min_fraction of at least
  // motion_min_readings readings, spanning at least half the window, must be inliers, and the
  // current frame must have a reading. A wall feature above the floor (a brick course) reads
  // D · h / (h − z) and moves faster than the floor; a reading that jumps between courses
  // scatters. Unlike the agreement above, the test does not lean on the cues, whose fused
  // distance far away reads short where a near structure stays in view (a bin in the corridor,
  // drive-3-02*), so the agreement rejected a right floor contact there (docs/calibration.md,
  // session 14). A window over which the floor point E − t crosses no more than motion_tol_rows
  // fails: an edge fixed in the image would pass it too (far away a row spans metres; a brick
  // course at the camera's height reads 15–20 m frame after frame; session 15b).
  double motion_window_m = 0.0;
  double motion_tol_rows = 0.5;
  double motion_min_fraction = 0.8;
  int motion_min_readings = 5;
  // The refinement to the strongest change in the next 2 rows considers only changes of the
  // first one's sign and stops at the first of the other sign; the sub-pixel parabola counts an
  // opposite-signed neighbour as 0 (false, the default: any sign; `squint calibrate` writes true
  // where it lowers the fused RMSE on its drives). On the ray-traced drives the end wall's foot
  // is a thin dark line one or two rows high (a contact shadow): its lower side is the opposite
  // step, often the stronger, and the refinement took it, a row below the foot on the floor
  // (drive-3-00c/r: mean row error +0.40 / +0.57, σ 0.75 / 0.91 rows at 5–15 m; with the sign
  // kept +0.02 / +0.10, σ 0.53 / 0.58; docs/calibration.md, session 14).
  bool refine_same_sign = false;
  // The lined-wall rule (lined_wall_rel_step > 0; 0 = off, the default; `squint calibrate` writes
  // 0.5 and keeps it only where it lowers the fused RMSE on its drives). The first edge below the
  // horizon is the end wall's foot only if the wall has no horizontal edges of its own. That is
  // checked on the wall itself: if the edge at row y, Δ = y − horizon rows below the horizon, were
  // the foot of a wall at that distance, the Δ rows just above the horizon would show the same
  // wall from the camera's height up to twice it. Where that band has a step of min_step between
  // neighbouring rows (brick courses, or the reflected corridor in a mirror end wall), the column
  // is lined and its edge is searched again, as the first step of at least lined_wall_rel_step
  // times the column's strongest step below the horizon (and at least min_step): the foot between
  // two surfaces is the column's strong change, a mortar line a weak one. Plain walls keep the
  // first edge, where the floor's own edges and reflections below a faint foot can be stronger
  // (drive-3-00*; docs/calibration.md, session 15). Where a column was searched again, the frame
  // reads only if its columns' edges lie on one line (kLinedWallRowSpread, floor_contact.hpp): a
  // course found again near a brick wall differs from column to column (session 15b).
  double lined_wall_rel_step = 0.0;
  std::string Validate() const;
};

struct DistanceOptions {
  // Per cue, indexed by DistanceCue: fusion weights (paper §5.2: time to contact most accurate).
  std::array<double, kDistanceCueCount> weights = {2.0, 1.0, 1.0};
  std::array<bool, kDistanceCueCount> enabled = {true, true, true};
  // g1 = ttc_scale * (τ · travelled per frame) + ttc_bias_m (identity by default).
  double ttc_scale = 1.0;
  double ttc_bias_m = 0.0;
  // Speed used for g1 when no travelled distance is given (m/s, times the frame interval);
  // 0 = none (then g1 needs odometry).
  double speed_mps = 0.0;
  // g2 = beta2 - alpha2 · J (eq. 4). Defaults are order-of-magnitude values for a robot at
  // ~0.4 m/s and 4–30 Hz; the calibration issue fits them per robot.
  double alpha2 = 200.0;
  double beta2 = 20.0;
  // g3 = alpha3 / (H(t-1) - H(t)) (§4.2.3), in m·nats.
  double alpha3 = 0.05;
  // Grey levels quantised to 2^bits bins for whole-glance entropy and Jeffrey divergence.
  int image_bits = 6;
  // Estimates outside [min_m, max_m] are "out of range".
  double min_m = 0.0;
  double max_m = 60.0;
  // Per cue: its validity window. A cue's (filtered, calibrated) estimate outside
  // [valid_min_m, valid_max_m] is "out of range" and not fused: e.g. time to contact where the
  // scene is not yet planar enough, Jeffrey divergence where the image barely changes. Fitted by
  // `squint calibrate` from the distances over which each cue's error stays small.
  std::array<double, kDistanceCueCount> valid_min_m = {0.0, 0.0, 0.0};
  std::array<double, kDistanceCueCount> valid_max_m = {60.0, 60.0, 60.0};
  // Per cue: how fast its error grows with its own estimate d (1/m). The fusion weight of an
  // estimate d is weights[c] / (1 + growth[c] · d)², i.e. inverse variance for an error
  // σ(d) = σ0 · (1 + growth · d) with weights[c] = 1/σ0² (0 = a constant weight).
  std::array<double, kDistanceCueCount> error_growth_per_m = {0.0, 0.0, 0.0};
  // Per cue: whether its estimate enters the fused distance (false: measured and reported, not
  // fused). `squint calibrate` keeps the subset of cues whose fusion has the lowest RMSE on the
  // calibration drives (docs/calibration.md).
  std::array<bool, kDistanceCueCount> fuse = {true, true, true};
  // No fused distance when its standard deviation, 1 / sqrt(Σ w) over the fused cues' weights
  // (the weights above are 1/σ² once calibrated), exceeds this (metres; 0 = off, the default).
  // `squint calibrate` sets it to the standard deviation of the true distances on its drives:
  // a fused estimate less certain than that says no more than "somewhere in a corridor".
  double fused_max_std_m = 0.0;
  // Temporal median over the last median_frames frames of each cue's model input (the paper
  // median-filters time to contact), so perceive, eval and explore all see filtered distances.
  // Time-to-contact values (metres) are first moved to the current frame by the odometry
  // travelled since. The window restarts when the robot does not drive forward. 1 = none.
  int median_frames = 9;
  // Time to contact compares the current glance with the one k frames back (k ≤
  // ttc_max_baseline_frames): the longest baseline whose travel is at most
  // ttc_baseline_fraction × the current distance estimate, so the image expands by a few
  // percent between the two glances (a one-frame baseline far from the end expands the image by
  // a fraction of a grey level; a long one near the end breaks the linearisation).
  int ttc_max_baseline_frames = 16;
  double ttc_baseline_fraction = 0.1;
  // Expansion centre of time to contact: the horizon row (the robot translates horizontally,
  // whatever the camera's pitch) when the camera is known, else the glance centre.
  bool ttc_centre_at_horizon = true;
  // Time to contact regresses the temporal change on the expansion term and the brightness
  // jointly, so that automatic gain between webcam frames (a 10–20 % change of mean brightness
  // on ../shared/data/drive-*) is not read as expansion or contraction. Off by default: on the
  // drive-* calibration split it made the calibrated time to contact worse, not better (the
  // brightness term also absorbs part of the expansion of a textured wall).
  bool ttc_gain_compensation = false;
  // Time to contact by a direct search over the image scale (default) instead of eq. 3's
  // linearised sums: the earlier glance, magnified by σ about the expansion centre, is compared
  // with the current one by normalised cross-correlation (invariant to the camera's gain and
  // offset) for σ from 1 to ttc_max_scale; the best σ gives d = s / (σ − 1) for a travel s over
  // the baseline (a plane facing the camera magnifies by d_earlier / d_now). The comparison
  // window is where the end wall would appear at the last filtered distance d̂: ±
  // ttc_window_half_width_m · f / d̂ columns and ± ttc_window_height_factor · camera height · f /
  // d̂ rows about the expansion centre (at least ttc_window_min_px), the whole glance before a
  // first estimate or without intrinsics. On ../shared/data/drive-* (test split) the
  // uncalibrated estimate is 0.65 m RMSE within 5 m against 3.3 m for eq. 3 (webcam gain jumps
  // of 10–20 % between frames swamp the linearised sums). With no distance estimate yet the
  // baseline is the longest whose travel stays within ttc_initial_baseline_m.
  bool ttc_scale_search = true;
  double ttc_max_scale = 1.5;
  double ttc_window_half_width_m = 1.5;
  double ttc_window_height_factor = 1.0;
  // The window is at least ±ttc_window_min_px columns and ±ttc_window_min_height_px rows (and
  // that before a first estimate; ttc_whole_glance_first: the whole glance then). Far away the
  // end wall alone is a few pixels of little texture at 32×24, and the estimate from it
  // saturated at 4–5 m (calibration drives drive-3-00*, per-frame median at 10 m ≈ 5 m, session
  // 3's 3 × 2 px minimum); a window of at least ±11 × ±8 keeps the corridor's converging edges,
  // floor and ceiling near the end, whose magnification tracked the distance to ~12 m there.
  double ttc_window_min_px = 11.0;
  double ttc_window_min_height_px = 8.0;
  bool ttc_whole_glance_first = true;
  // Both glances are smoothed by a 3×3 binomial filter before the scale search: the bilinear
  // magnification of the earlier glance smooths it, and the unsmoothed current glance then
  // matches best at a magnification too large (a distance too short far away).
  bool ttc_smooth = true;
  double ttc_initial_baseline_m = 0.4;
  // The scale search gives no reading until the glance history spans this much driving or is
  // full (kMaxTtcBaselineFrames + 1 glances), after a start or a stop: the first one-frame baselines read noise as a short distance, which
  // then kept the baseline short (0.5 chosen on the calibration drives drive-3-00*: 0.3 / 0.5 /
  // 1.0 m gave fused 3.95 / 3.72 / 3.89 m RMSE at 5–15 m there). 0 = none.
  double ttc_warmup_m = 0.5;
  // The scale search gives no estimate where the window's grey-level standard deviation is
  // below ttc_min_contrast or the best NCC below ttc_min_ncc.
  double ttc_min_contrast = 2.0;
  double ttc_min_ncc = 0.8;
  // Far-structure cells (0 = off, the default): the scale search's window is also cut into
  // cells of about ttc_cell_px × ttc_cell_px glance pixels, each cell's magnification is refined
  // on its own (Gauss–Newton from the window's), and the estimate is the ttc_cell_quantile of the
  // cells' magnifications (cells with contrast and NCC above the thresholds above; fewer than
  // ttc_cell_min_count such cells: the window's). A low quantile keeps the farthest structure:
  // near textured walls, door frames or an obstacle in the corridor expand faster than the end
  // wall and otherwise pull the window's single magnification up (a distance too short).
  double ttc_cell_px = 0.0;
  double ttc_cell_quantile = 0.25;
  int ttc_cell_min_count = 3;
  // A cell counts only when the standard error of its magnification is at most this fraction of
  // the expected expansion (σ − 1 predicted from the last estimate and the travel, else the
  // window's): a cell without texture is noise around no expansion, i.e. "very far".
  double ttc_cell_max_se_fraction = 1e9;
  // Cells only where the window's magnification shows at least this expansion (σ − 1); below,
  // the window's magnification stands (a short baseline far away: at 30 Hz the 16-frame
  // history spans 0.2 m, σ − 1 ≈ 0.02 at 10 m, and single cells are noise). 0 = always.
  double ttc_cell_min_expansion = 0.0;
  // Only the ttc_cell_nearest cells whose centres are nearest the expansion centre count (0 =
  // all cells); the search stops once that many answered, and ttc_cell_min_count is counted
  // among them.
  int ttc_cell_nearest = 0;
  // ... only while the window is at its minimum size (far away; nearer, the window sized by the
  // end wall holds the end wall only and every cell counts).
  bool ttc_cell_nearest_at_min_window = false;
  // Process(frame) gives time to contact an area-averaged glance of the frame (the other
  // measures keep options.sampling): point sampling aliases fine wall texture, which then does
  // not scale with the distance (drive-* test split: 1.66 m RMSE within 5 m point-sampled,
  // 0.65 m area-averaged). ProcessGlance() uses the glance it is given.
  bool ttc_area_glance = true;
  // Time to contact's own image (1 = the glance, the default): with s > 1 Process(frame) gives
  // the scale search an area-averaged image of round(32·s) × round(24·s) pixels of the frame
  // (when the frame is at least that large; else the glance), the other measures keep the 32×24
  // glance. Every window and cell size above stays in glance pixels (the same angles); the
  // finer image resolves the end wall far away, where at 32×24 it is a few pixels, one cell.
  // Needs ttc_scale_search; ProcessGlance() has no frame and uses the glance.
  double ttc_glance_scale = 1.0;

  // Fusion weight of cue `cue`'s estimate `dist_m`: weights[cue] / (1 + growth · max(0, dist_m))²
  // (error_growth_per_m above). The Perceiver's fusion, the eval's unfiltered average and the
  // calibration's choice of fused cues all weigh with it.
  double FusionWeight(int cue, double dist_m) const;

  FloorContactOptions floor_contact;

  std::string Validate() const;
};

// Upper bounds of the fixed-size buffers behind the options above.
inline constexpr int kMaxDistanceMedianFrames = 31;
inline constexpr int kMaxTtcBaselineFrames = 32;

struct GateOptions {
  bool enabled = true;
  // Skip full processing when |H(t) - H(t-1)| / H(reference) < threshold (§5.3: 0.01).
  // Default 0.05, chosen on the simulator's calibration drives (corridor-0…4, 30 Hz, 0.4 m/s;
  // docs/eval/gate_sweep.py): the frames that the paper's 0.01 lets through between the forced
  // ones are the abrupt views (doors, lights) on which the memory-less heading is worst (test
  // drives: 6.71° on them, 5.84° on the forced frames, 6.04° on every frame), so the processed
  // frames were a harder sample than the whole drive. At 0.05 only large changes (a new
  // corridor, a turn) trigger processing and the forced cadence below supplies the rest:
  // calibration drives 90.9 % skipped, processed 6.30° against 6.38° on every frame.
  double threshold = 0.05;
  // What H(t-1) is. false: the previous frame (the paper), so a slow drift of the view never
  // triggers processing and the processed frames are exactly the abrupt ones (doors, lights,
  // gain jumps), a biased, harder sample. true: the last processed frame, so the change is
  // measured against what the robot last looked at, and a slow change accumulates until it
  // crosses the threshold.
  // Default false: on the simulator's test drives (corridor-5…9, 30 Hz) comparing with the
  // last processed frame skipped fewer frames (83 % vs 87 %) without a better heading.
  bool compare_with_last_processed = false;
  // Process at least every (max_skipped_frames + 1)-th frame whatever the entropy does, so
  // that the estimates never go stale for long and the processed frames are not only the
  // abrupt ones (0 = no limit). 10: a third of a second at 30 Hz.
  int max_skipped_frames = 10;

  std::string Validate() const;
};

struct CorridorOptions {
  GlanceSampling sampling = GlanceSampling::kPoint;
  HeadingOptions heading;
  DistanceOptions distance;
  GateOptions gate;

  // Empty when valid, otherwise what is wrong (one line, naming the field).
  std::string Validate() const;
};

}  // namespace squint::corridor
