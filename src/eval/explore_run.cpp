// The closed-loop exploration runner: simulator → 32×24 glance → corridor perception → explorer
// → robot, with ground truth kept aside for scoring (coverage, collisions) and logs.
#include "squint/eval/explore_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/corridor/perceiver.hpp"
#include "squint/sim/ground_truth.hpp"

namespace squint::eval {

CameraModel BelowHorizon(CameraModel camera) {
  const int crop_top = std::clamp(static_cast<int>(std::floor(camera.HorizonRow())) - 4, 0, camera.height / 2);
  camera.height -= crop_top;
  camera.cy -= crop_top;
  return camera;
}

namespace {

double ThreadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double Or(const std::optional<double>& v) { return v ? *v : kNaN; }

// The translation-sensitive cue for centring. The paper names bright pixels (§4.1.5); in the
// simulator's corridors the symmetry axis moves with translation far more consistently (about
// 40° per metre of lateral offset, against a bright-pixel cue that is often absent), so it is used.
std::optional<double> CentreCue(const corridor::PerceptionResult& r) {
  double sum = 0.0;
  int n = 0;
  for (corridor::HeadingCue cue : {corridor::HeadingCue::kSymmetry}) {
    const auto& m = r.Heading(cue);
    if (m.heading_deg) {
      sum += *m.heading_deg;
      ++n;
    }
  }
  if (n == 0) return std::nullopt;
  return sum / n;
}

}  // namespace

obstacles::IptOptions LoopIptOptions() {
  obstacles::IptOptions o;
  o.features.detector = obstacles::Detector::kOrb;
  o.features.orb_upright = false;  // OpenCV's ORB (Harris, oriented): the loop as tuned with it
  return o;
}

std::string ExploreRunOptions::Validate() const {
  if (!(minutes > 0.0) || !std::isfinite(minutes)) return "minutes must be positive";
  if (minutes > 24 * 60.0) return "minutes must be at most 1440 (one simulated day)";
  if (!(frame_rate_hz >= 1.0 && frame_rate_hz <= 200.0)) return "frame_rate_hz must be in [1, 200]";
  if (glance_supersample < 1 || glance_supersample > 8) return "glance_supersample must be in [1, 8]";
  if (!(sensor_noise_sigma >= 0.0) || !std::isfinite(sensor_noise_sigma)) return "sensor_noise_sigma must be >= 0";
  if (sonar_every < 1 || sonar_every > 30) return "sonar_every must be in [1, 30]";
  if (std::string e = light_line.Validate(); !e.empty()) return e;
  if (wall_lines_every < 1 || wall_lines_every > 30) return "wall_lines_every must be in [1, 30]";
  if (wall_lines_width < 16 || wall_lines_width > 1024 || wall_lines_height < 16 || wall_lines_height > 1024)
    return "wall_lines_width and wall_lines_height must be in [16, 1024]";
  if (wall_lines_supersample < 1 || wall_lines_supersample > 8) return "wall_lines_supersample must be in [1, 8]";
  if (std::string e = wall_lines.Validate(); !e.empty()) return e;
  if (sonar_width < 16 || sonar_width > 640 || sonar_height < 12 || sonar_height > 480) return "sonar size must be within 16x12..640x480";
  if (sonar_supersample < 1 || sonar_supersample > 8) return "sonar_supersample must be in [1, 8]";
  if (std::string e = sonar.Validate(); !e.empty()) return "sonar." + e;
  if (ipt_every < 1 || ipt_every > 60) return "ipt_every must be in [1, 60]";
  if (ipt_width < 32 || ipt_width > 1280 || ipt_height < 24 || ipt_height > 960) return "ipt size must be within 32x24..1280x960";
  if (!(ipt_min_baseline_m >= 0.0 && ipt_min_baseline_m <= 1.0)) return "ipt_min_baseline_m must be in [0, 1]";
  if (!(ipt_max_pair_s > 0.0 && ipt_max_pair_s <= 10.0)) return "ipt_max_pair_s must be in (0, 10]";
  if (!(ipt_roi_beyond_view_m >= 0.0 && ipt_roi_beyond_view_m <= 10.0)) return "ipt_roi_beyond_view_m must be in [0, 10]";
  if (ipt_bottom_margin_px < 0 || ipt_bottom_margin_px > 20) return "ipt_bottom_margin_px must be in [0, 20]";
  if (ipt_supersample < 1 || ipt_supersample > 8) return "ipt_supersample must be in [1, 8]";
  if (std::string e = ipt.Validate(); !e.empty()) return "ipt." + e;
  if (std::string e = avoid.Validate(); !e.empty()) return "avoid." + e;
  if (std::string e = advice.Validate(); !e.empty()) return "advice." + e;
  if (std::string e = explorer.Validate(); !e.empty()) return "explorer." + e;
  if (std::string e = perception.Validate(); !e.empty()) return "perception." + e;
  if (std::string e = odometry.Validate(); !e.empty()) return "odometry." + e;
  return {};
}

ExploreRunResult RunExplore(const sim::World& world, const ExploreRunOptions& options,
                            const std::function<void(double)>& progress) {
  if (std::string e = options.Validate(); !e.empty()) throw Error("explore: " + e);
  const auto wall_start = std::chrono::steady_clock::now();
  const double dt = 1.0 / options.frame_rate_hz;

  const CameraModel glance_camera = world.camera.Model().Scaled(corridor::kGlanceWidth, corridor::kGlanceHeight);
  sim::RenderOptions render;
  render.supersample = options.glance_supersample;
  render.noise_sigma = options.sensor_noise_sigma;
  render.seed = options.seed;
  sim::Renderer renderer(world, glance_camera, render);
  corridor::CorridorOptions perception = options.perception;
  if (options.explorer.filtered_axis_gain > 0.0) perception.heading.filter.enabled = true;
  corridor::Perceiver perceiver(perception, glance_camera);

  sim::RobotOptions robot_options;
  robot_options.step_s = dt;
  robot_options.odometry = options.odometry;
  robot_options.odometry.seed = options.seed * 7919u + 17u;
  const Pose2 start = options.start.value_or(world.start);
  sim::Robot robot(world, start, robot_options);
  explore::ExplorerOptions explorer_options = options.explorer;
  explorer_options.robot_radius_m = world.robot.radius_m;
  explore::Explorer explorer(explorer_options);

  // The visual sonar's frame: the same camera at a small size, rendered at a sub-rate.
  std::optional<sim::Renderer> sonar_renderer;
  std::optional<explore::VisualSonar> sonar;
  cv::Mat sonar_image;
  if (options.visual_sonar) {
    const CameraModel sonar_camera = BelowHorizon(world.camera.Model().Scaled(options.sonar_width, options.sonar_height));
    sim::RenderOptions sr = render;
    sr.supersample = options.sonar_supersample;
    sr.seed = options.seed + 1000003u;
    sonar_renderer.emplace(world, sonar_camera, sr);
    sonar.emplace(sonar_camera, options.sonar);
    sonar_image.create(sonar_camera.height, sonar_camera.width, CV_8UC1);
  }

  // The walls' lines' frame: the camera at wall_lines_width × wall_lines_height, cropped like the
  // sonar's (rows from a little above the horizon down).
  std::optional<sim::Renderer> wall_renderer;
  std::optional<CameraModel> wall_camera;
  cv::Mat wall_image, wall_fine;
  std::vector<float> wall_bottom_texture;  // the walls' lines' frame's bottom texture per column
  if (options.explorer.wall_line_axis_gain > 0.0) {
    const CameraModel wc = BelowHorizon(world.camera.Model().Scaled(options.wall_lines_width, options.wall_lines_height));
    sim::RenderOptions wr = render;
    wr.seed = options.seed + 3000003u;
    const int n = options.wall_lines_supersample;
    if (options.wall_lines_binned && n > 1) {
      // The camera's image downsampled: n × n pixels, each with its own sensor noise, per pixel.
      const CameraModel fine = wc.Scaled(n * wc.width, n * wc.height);
      wr.supersample = 1;
      wall_renderer.emplace(world, fine, wr);
      wall_fine.create(fine.height, fine.width, CV_8UC1);
    } else {
      wr.supersample = n;
      wall_renderer.emplace(world, wc, wr);
    }
    wall_camera = wc;
    wall_image.create(wc.height, wc.width, CV_8UC1);
  }

  // The obstacle pipeline's frames: the camera at ipt_width × ipt_height, rendered every ipt_every
  // frames while following; each is paired with the previous one.
  std::optional<sim::Renderer> ipt_renderer;
  std::optional<obstacles::IptPipeline> ipt;
  std::optional<obstacles::Avoider> avoider;
  std::optional<obstacles::PolarMapper> polar;
  obstacles::GapOptions avoid_gap;
  std::vector<obstacles::ContactPoint> kept_contacts;
  std::vector<obstacles::Gap> gaps;
  explore::ObstacleAdviceOptions advice_options = options.advice;
  advice_options.robot_radius_m = world.robot.radius_m;
  cv::Mat ipt_previous, ipt_current;
  Pose2 ipt_previous_odom;
  double ipt_previous_s = 0.0;
  bool have_ipt_previous = false;
  obstacles::PairResult pair;
  if (options.obstacle_pipeline) {
    const CameraModel ipt_camera = world.camera.Model().Scaled(options.ipt_width, options.ipt_height);
    sim::RenderOptions ir = render;
    ir.supersample = options.ipt_supersample;
    ir.seed = options.seed + 2000003u;
    ipt_renderer.emplace(world, ipt_camera, ir);
    ipt.emplace(ipt_camera, options.ipt);
    obstacles::AvoidOptions avoid = options.avoid;
    avoid.gap.robot_radius_m = world.robot.radius_m;
    avoider.emplace(ipt_camera, avoid);
    // The region of interest reaches ipt_roi_beyond_view_m beyond the nearest floor in view (a
    // camera pitched only a little down, like the default world's, sees no floor nearer than
    // ≈ 1.2 m: a 1.5 m ROI would hold an obstacle's foot for a single pair).
    obstacles::PolarMapOptions polar_options = avoid.polar;
    if (const auto near = ipt_camera.FloorPoint({0.5 * ipt_camera.width, ipt_camera.height - 1.0}))
      polar_options.roi_radius_m = std::max(polar_options.roi_radius_m, near->norm() + options.ipt_roi_beyond_view_m);
    polar.emplace(ipt_camera, polar_options);
    avoid_gap = avoid.gap;
    kept_contacts.reserve(256);
    gaps.reserve(64);
    ipt_previous.create(ipt_camera.height, ipt_camera.width, CV_8UC1);
    ipt_current.create(ipt_camera.height, ipt_camera.width, CV_8UC1);
  }

  ExploreRunResult out;
  out.world_name = world.name;
  out.start = start;
  const long frames = std::lround(options.minutes * 60.0 * options.frame_rate_hz);
  out.true_path.reserve(static_cast<std::size_t>(frames) + 1);
  if (options.keep_trace) out.trace.reserve(static_cast<std::size_t>(frames));

  corridor::Glance glance;
  MutableGrayView view{glance.pixels.data(), corridor::kGlanceWidth, corridor::kGlanceHeight, corridor::kGlanceWidth};
  Pose2 prev_odom = robot.OdomPose();
  double perception_cpu = 0.0;
  long processed_frames = 0;
  std::size_t events_seen = 0;
  std::vector<double> axis_errors;  // |axis error| (degrees) on the frames spent following
  axis_errors.reserve(static_cast<std::size_t>(frames));
  const long progress_every = std::max(1L, frames / 200);

  for (long f = 0; f < frames; ++f) {
    const Pose2 world_T_robot = robot.TruePose();
    out.true_path.push_back(world_T_robot);
    renderer.Render(world_T_robot, view, nullptr, 0, nullptr, 0, static_cast<std::uint64_t>(f));
    const Pose2 odom = robot.OdomPose();
    const Pose2 moved = Between(prev_odom, odom);
    const double travelled = moved.x;
    prev_odom = odom;

    // Perception (timed: the CPU budget is the paper's rapid-perception point).
    double heading_prior_deg = 0.0;
    if (explorer.TakeHeadingFilterReset(&heading_prior_deg))
      perceiver.ResetHeadingFilter(heading_prior_deg, explorer_options.heading_filter_prior_std_deg);
    if (explorer.TakeGateReset() || explorer.WantsFullProcessing()) perceiver.ResetGateReference();
    const double cpu0 = ThreadCpuSeconds();
    const corridor::PerceptionResult r = perceiver.ProcessGlance(glance, travelled, f == 0 ? 0.0 : dt, RadToDeg(moved.yaw));
    perception_cpu += ThreadCpuSeconds() - cpu0;
    if (r.processed) ++processed_frames;

    explore::Percept p;
    p.stamp_s = f * dt;
    p.odom_T_robot = odom;
    p.processed = r.processed;
    p.heading_deg = r.heading_instant_deg;  // the per-frame fusion (r.heading_deg without the filter)
    if (perception.heading.filter.enabled) p.heading_filtered_deg = r.heading_deg;
    p.dist_end_m = r.dist_end_m;
    p.centre_heading_deg = r.processed ? CentreCue(r) : std::nullopt;
    if (explorer_options.light_centre_gain > 0.0 || explorer_options.light_axis_gain > 0.0) {
      const double cpu2 = ThreadCpuSeconds();
      const explore::LightLine light =
          explore::FindLightLine(GrayView{glance.pixels.data(), corridor::kGlanceWidth, corridor::kGlanceHeight, corridor::kGlanceWidth},
                                 glance_camera, options.light_line);
      perception_cpu += ThreadCpuSeconds() - cpu2;
      if (light.valid) {
        p.light_lateral_m = light.LateralM(options.light_line.nominal_height_m);
        p.light_heading_deg = RadToDeg(-light.direction_rad);
      }
    }
    p.glance_entropy_nats = r.entropy;
    // While following; while probing too where the explorer takes a side the lines show free as open.
    // While scanning and aligning too where the explorer takes its axis from them at a standstill.
    // (explorer.wall_line_align_over_deg alone: there the frame gives the lines' heading only, so a
    // run whose lines never override the glance is the run without it step for step.)
    const bool standstill = explorer.State() == explore::ExploreState::kScan || explorer.State() == explore::ExploreState::kAlign;
    const bool heading_only = standstill && !options.explorer.wall_line_align;
    const bool wall_lines_now = explorer.State() == explore::ExploreState::kFollow ||
                                (explorer.State() == explore::ExploreState::kProbe && options.explorer.wall_line_free_m > 0.0) ||
                                (standstill && explorer.WantsAlignLines());
    if (wall_renderer && wall_lines_now && f % options.wall_lines_every == 0) {
      MutableGrayView wv{wall_image.data, wall_image.cols, wall_image.rows, static_cast<std::ptrdiff_t>(wall_image.step)};
      double cpu4 = 0.0;
      if (!wall_fine.empty()) {
        MutableGrayView fv{wall_fine.data, wall_fine.cols, wall_fine.rows, static_cast<std::ptrdiff_t>(wall_fine.step)};
        wall_renderer->Render(world_T_robot, fv, nullptr, 0, nullptr, 0, static_cast<std::uint64_t>(f));
        cpu4 = ThreadCpuSeconds();  // the downsampling is the robot's own work
        cv::resize(wall_fine, wall_image, wall_image.size(), 0.0, 0.0, cv::INTER_AREA);
      } else {
        wall_renderer->Render(world_T_robot, wv, nullptr, 0, nullptr, 0, static_cast<std::uint64_t>(f));
        cpu4 = ThreadCpuSeconds();
      }
      explore::WallLines wl = explore::FindWallLines(wv, *wall_camera, options.wall_lines);
      perception_cpu += ThreadCpuSeconds() - cpu4;
      if (wl.valid) p.wall_line_heading_deg = wl.HeadingDeg();
      if (!heading_only) {
        wall_bottom_texture = std::move(wl.bottom_texture);
        p.wall_bottom_texture = &wall_bottom_texture;
        p.wall_line_corridor_ahead_m = wl.valid ? wl.corridor_ahead_m : 0.0;
        if (wl.valid) {
          p.wall_line_direction_deg = RadToDeg(wl.direction_rad);
          p.wall_line_offset_m = wl.offset_m;
          if (2 * wl.parallel_inliers >= options.wall_lines.min_inliers) p.wall_line_parallel_offset_m = wl.parallel_offset_m;
        }
      }
    }
    if (sonar && f % options.sonar_every == 0) {
      MutableGrayView sv{sonar_image.data, sonar_image.cols, sonar_image.rows, static_cast<std::ptrdiff_t>(sonar_image.step)};
      sonar_renderer->Render(world_T_robot, sv, nullptr, 0, nullptr, 0, static_cast<std::uint64_t>(f));
      const double cpu1 = ThreadCpuSeconds();
      p.sonar = &sonar->Process(sv);
      p.sonar_near_blind_m = sonar->NearBlindRangeM();
      p.sonar_wall_lines = sonar->WallLineFraction();
      p.sonar_profile = &sonar->HorizonProfile();
      perception_cpu += ThreadCpuSeconds() - cpu1;
    }
    // The obstacle pipeline, only while following (a pair needs forward motion; turning in place
    // gives pure rotations). Leaving the follow state drops the previous frame.
    if (ipt && explorer.State() != explore::ExploreState::kFollow) have_ipt_previous = false;
    // A pair needs a baseline: the previous frame is kept until the odometry moved ipt_min_baseline_m
    // from it (or it is older than ipt_max_pair_s, when it is replaced without a pair).
    const bool ipt_due = ipt && explorer.State() == explore::ExploreState::kFollow && f % options.ipt_every == 0;
    const double ipt_baseline_m = have_ipt_previous ? (odom.Translation() - ipt_previous_odom.Translation()).norm() : 0.0;
    if (ipt_due && have_ipt_previous && ipt_baseline_m < options.ipt_min_baseline_m &&
        p.stamp_s - ipt_previous_s <= options.ipt_max_pair_s) {
      // wait for more baseline
    } else if (ipt_due) {
      if (ipt_baseline_m < options.ipt_min_baseline_m) have_ipt_previous = false;
      MutableGrayView iv{ipt_current.data, ipt_current.cols, ipt_current.rows, static_cast<std::ptrdiff_t>(ipt_current.step)};
      ipt_renderer->Render(world_T_robot, iv, nullptr, 0, nullptr, 0, static_cast<std::uint64_t>(f));
      if (have_ipt_previous) {
        const double cpu3 = ThreadCpuSeconds();
        ipt->Process(ipt_previous, ipt_current, ipt_previous_odom, odom, &pair);
        ++out.summary.ipt_pairs;
        if (pair.Ok()) {
          const obstacles::AvoidResult& ar = avoider->Process(ipt_current, pair.features);
          // The map again without the contacts whose outline ran off the image's bottom edge.
          kept_contacts.clear();
          const double bottom_row = ipt_current.rows - 1 - options.ipt_bottom_margin_px;
          for (const obstacles::ContactPoint& c : ar.contacts)
            if (!options.ipt_drop_bottom_contacts || c.pixel.y() < bottom_row) kept_contacts.push_back(c);
          const obstacles::PolarMap& map = polar->Build(kept_contacts, ar.ground_floor_m);
          obstacles::FindGaps(map, avoid_gap, &gaps);
          p.obstacles = explore::MakeObstacleAdvice(map, obstacles::ChooseSteering(gaps), advice_options);
          ++out.summary.ipt_classified;
          if (p.obstacles->in_path) ++out.summary.advice_in_path;
        }
        const double used = ThreadCpuSeconds() - cpu3;
        perception_cpu += used;
        out.summary.ipt_cpu_seconds += used;
      }
      std::swap(ipt_previous, ipt_current);
      ipt_previous_odom = odom;
      ipt_previous_s = p.stamp_s;
      have_ipt_previous = true;
    }
    const double cpu2 = ThreadCpuSeconds();
    const explore::Command cmd = explorer.Step(p);
    if (p.sonar) perception_cpu += ThreadCpuSeconds() - cpu2;  // the sonar memory update runs inside Step

    const sim::StepResult step = robot.Step(cmd.v_mps, cmd.omega_rps);
    if (step.collided && out.summary.first_hit.empty()) {
      out.summary.first_collision_s = static_cast<double>(f) * dt;
      out.summary.first_collision_pose = robot.TruePose();
      out.summary.first_hit = step.hit;
    }

    bool first_setoff = false;
    for (; events_seen < explorer.Events().size(); ++events_seen) {
      out.marks.push_back(ExploreMark{explorer.Events()[events_seen], world_T_robot});
      if (explorer.Events()[events_seen].kind == explore::ExploreEvent::Kind::kScanDone &&
          std::isnan(out.summary.setoff_seconds))
        first_setoff = true;
    }
    // How well the explorer knows the corridor's axis (ground truth; the loop does not see it).
    // The ground truth is looked up once per frame, for these figures and the trace.
    const bool following = explorer.State() == explore::ExploreState::kFollow;
    std::optional<GroundTruth> gt;
    if (following || first_setoff || options.keep_trace) gt = sim::GroundTruthAt(world, world_T_robot);
    if (following || first_setoff) {
      if (const std::optional<double> true_heading = gt->heading_deg) {
        const double err = std::remainder(*true_heading - explorer.HeadingEstimateDeg(), 90.0);
        if (following) axis_errors.push_back(std::abs(err));
        if (first_setoff) {
          out.summary.setoff_seconds = p.stamp_s;
          out.summary.setoff_axis_error_deg = err;
        }
      }
    }

    if (options.keep_trace) {
      ExploreTraceRow row;
      row.t_s = p.stamp_s;
      row.world_T_robot = world_T_robot;
      row.odom_T_robot = odom;
      row.processed = r.processed;
      row.heading_deg = Or(r.heading_deg);
      row.centre_heading_deg = Or(p.centre_heading_deg);
      row.dist_end_m = Or(r.dist_end_m);
      row.entropy = r.entropy;
      row.heading_est_deg = explorer.HeadingEstimateDeg();
      row.dist_est_m = explorer.DistEndEstimateM() >= 0.0 ? explorer.DistEndEstimateM() : kNaN;
      row.true_heading_deg = Or(gt->heading_deg);
      row.true_lateral_m = Or(gt->lateral_m);
      row.true_dist_end_m = Or(gt->dist_end_m);
      row.state = explorer.State();
      row.v_mps = cmd.v_mps;
      row.omega_rps = cmd.omega_rps;
      row.collided = step.collided;
      row.light_lateral_m = Or(p.light_lateral_m);
      row.light_heading_deg = Or(p.light_heading_deg);
      double light_est = kNaN;
      row.light_lateral_est_m = explorer.LightLateral(p.stamp_s, odom, &light_est) ? light_est : kNaN;
      out.trace.push_back(row);
    }
    if (progress && f % progress_every == 0) progress(static_cast<double>(f) / static_cast<double>(frames));
  }
  out.true_path.push_back(robot.TruePose());
  if (progress) progress(1.0);

  ExploreSummary& s = out.summary;
  s.sim_seconds = robot.Time();
  s.distance_m = robot.DistanceTravelled();
  s.collisions = robot.Collisions();
  s.coverage = CorridorCoverage(world, out.true_path);
  s.ends_detected = explorer.EndsDetected();
  s.turns = explorer.Turns();
  s.frames = frames;
  s.frames_fully_processed = processed_frames;
  s.perception_cpu_seconds = perception_cpu;
  s.override_frames = explorer.ObstacleOverrides();
  s.obstacle_stops = explorer.ObstacleStops();
  s.mirror_scans = explorer.MirrorsFound();
  s.align_line_overrides = explorer.AlignLineOverrides();
  s.scan_entropy_skips = explorer.ScanEntropySkips();
  s.wall_keep_frames = explorer.WallKeepFrames();
  s.scan_wall_entropy_skips = explorer.ScanWallEntropySkips();
  s.contacts_felt = explorer.ContactsFelt();
  s.near_edges = explorer.NearEdgesRanged();
  if (!axis_errors.empty()) {
    const auto p90 = axis_errors.begin() + static_cast<std::ptrdiff_t>(0.9 * static_cast<double>(axis_errors.size() - 1));
    std::nth_element(axis_errors.begin(), p90, axis_errors.end());
    s.axis_error_p90_deg = *p90;
    s.axis_error_over_10deg =
        static_cast<double>(std::count_if(axis_errors.begin(), axis_errors.end(), [](double e) { return e > 10.0; })) /
        static_cast<double>(axis_errors.size());
  }
  out.topo = explorer.Map().Nodes();
  // "Could not proceed": the robot covered almost nothing new, or barely moved.
  const double expected_m = options.explorer.cruise_speed_mps * s.sim_seconds;
  s.proceeded = s.distance_m >= std::max(5.0, 0.1 * expected_m) && s.coverage >= 0.05;
  char line[320];
  if (s.proceeded) {
    std::snprintf(line, sizeof line,
                  "explored %.0f%% of %.0f m of corridor, drove %.0f m in %.1f min, %d ends, %d turns, %d collisions",
                  100.0 * s.coverage, world.CorridorLength(), s.distance_m, s.sim_seconds / 60.0, s.ends_detected, s.turns,
                  s.collisions);
  } else {
    std::snprintf(line, sizeof line,
                  "exploration could not proceed: drove only %.1f m in %.1f min (coverage %.0f%%, %d ends, %d turns, "
                  "%d collisions); see map.png",
                  s.distance_m, s.sim_seconds / 60.0, 100.0 * s.coverage, s.ends_detected, s.turns, s.collisions);
  }
  s.outcome = line;
  if (ipt) {
    std::snprintf(line, sizeof line,
                  "; obstacle pipeline: %ld pairs, %ld classified, %ld with an obstacle in the path, %ld override frames, "
                  "%d stop-and-turns",
                  s.ipt_pairs, s.ipt_classified, s.advice_in_path, s.override_frames, s.obstacle_stops);
    s.outcome += line;
  }
  s.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return out;
}

double CorridorCoverage(const sim::World& world, const std::vector<Pose2>& path, double sample_step_m) {
  SQUINT_ENSURE(sample_step_m > 0.0, "sample_step_m must be positive");
  // Decimate the path: a point every 5 cm of travel is plenty at a 0.1 m sample step.
  std::vector<Eigen::Vector2d> pts;
  for (const Pose2& p : path)
    if (pts.empty() || (p.Translation() - pts.back()).norm() >= 0.05) pts.push_back(p.Translation());
  double total = 0.0, covered = 0.0;
  for (const sim::Corridor& c : world.corridors) {
    const double length = c.Length();
    const int n = std::max(1, static_cast<int>(std::ceil(length / sample_step_m)));
    const double piece = length / n;
    const double r2 = 0.25 * c.width_m * c.width_m;
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d q = c.from + (c.to - c.from) * ((i + 0.5) / n);
      total += piece;
      for (const Eigen::Vector2d& p : pts) {
        if ((p - q).squaredNorm() <= r2) {
          covered += piece;
          break;
        }
      }
    }
  }
  return total > 0.0 ? covered / total : 0.0;
}

std::vector<Pose2> SeededStarts(const sim::World& world, int count, std::uint64_t seed) {
  SQUINT_ENSURE(count >= 0, "count must be >= 0");
  std::vector<Pose2> starts;
  if (count == 0) return starts;
  starts.push_back(world.start);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double r = world.robot.radius_m;
  auto free_pose = [&](const Eigen::Vector2d& p) {
    return world.IsFree(p) && world.DistanceToWalls(p) > r + 0.06 && world.DistanceToObstacles(p) > r + 0.1;
  };
  double total = 0.0;
  for (const sim::Corridor& c : world.corridors) total += c.Length();
  auto pick = [&](double lateral_frac, std::optional<double> yaw_rel) -> std::optional<Pose2> {
    for (int attempt = 0; attempt < 200; ++attempt) {
      double u = unit(rng) * total;
      const sim::Corridor* corr = &world.corridors.front();
      for (const sim::Corridor& c : world.corridors) {
        corr = &c;
        if (u <= c.Length()) break;
        u -= c.Length();
      }
      const double len = corr->Length();
      if (len < 3.0) continue;
      const double along = 1.5 + unit(rng) * (len - 3.0);
      const Eigen::Vector2d axis = corr->Axis();
      const Eigen::Vector2d left(-axis.y(), axis.x());
      const double half = 0.5 * corr->width_m - r - 0.1;
      const double side = unit(rng) < 0.5 ? -1.0 : 1.0;
      const double lateral = lateral_frac >= 0.0 ? side * lateral_frac * half : (2.0 * unit(rng) - 1.0) * half;
      const Eigen::Vector2d p = corr->from + along * axis + lateral * left;
      if (!free_pose(p)) continue;
      const double axis_yaw = std::atan2(axis.y(), axis.x());
      const double yaw = yaw_rel ? axis_yaw + (side > 0 ? *yaw_rel : -*yaw_rel) : WrapPi(2.0 * kPi * unit(rng));
      return Pose2{p.x(), p.y(), WrapPi(yaw)};
    }
    return std::nullopt;
  };
  while (static_cast<int>(starts.size()) < count) {
    std::optional<Pose2> p;
    if (starts.size() == 1) p = pick(0.0, kPi / 2);          // on the centre line, facing a side wall
    else if (starts.size() == 2) p = pick(1.0, 0.3);         // close to a wall, turned toward it
    else p = pick(-1.0, std::nullopt);
    if (!p) throw Error("explore: world '" + world.name + "' has no free start pose for the robot");
    starts.push_back(*p);
  }
  return starts;
}

}  // namespace squint::eval
