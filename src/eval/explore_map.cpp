// Outputs of an exploration run: the map figure (paper Fig. 11: floor plan, path, end-of-corridor
// detections, numbered turn points, junctions), summary.json, trace.csv and events.csv.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/eval/explore_run.hpp"
#include "squint/eval/plot.hpp"
#include "squint/io/atomic_output.hpp"
#include "squint/sim/floor_plan.hpp"

namespace squint::eval {
namespace {

const cv::Scalar kPathBgr(40, 40, 220);     // red
const cv::Scalar kEndBgr(40, 170, 40);      // green
const cv::Scalar kTurnBgr(160, 60, 20);     // dark blue
const cv::Scalar kStartBgr(200, 120, 0);
const cv::Scalar kStallBgr(0, 140, 255);    // orange

void DrawDashed(cv::Mat& img, const std::vector<cv::Point2d>& pts, const cv::Scalar& bgr, double dash_px) {
  double carried = 0.0;
  bool on = true;
  for (std::size_t i = 1; i < pts.size(); ++i) {
    cv::Point2d a = pts[i - 1];
    const cv::Point2d b = pts[i];
    double seg = std::hypot(b.x - a.x, b.y - a.y);
    while (seg > 1e-9) {
      const double step = std::min(seg, dash_px - carried);
      const cv::Point2d c = a + (b - a) * (step / seg);
      if (on) cv::line(img, a, c, bgr, 1, cv::LINE_AA);
      carried += step;
      seg -= step;
      a = c;
      if (carried >= dash_px - 1e-9) {
        carried = 0.0;
        on = !on;
      }
    }
  }
}

std::string Cell(double v, int decimals) {
  if (!std::isfinite(v)) return {};
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

}  // namespace

cv::Mat DrawExploreMap(const sim::World& world, const ExploreRunResult& run, const std::string& title) {
  sim::FloorPlanOptions fo;
  const sim::Box2 b = world.Bounds();
  const double extent = std::max(b.x1 - b.x0, b.y1 - b.y0);
  fo.px_per_m = std::clamp(900.0 / std::max(extent, 1.0), 8.0, 40.0);
  fo.draw_lights = false;
  sim::FloorPlan plan(world, fo);
  cv::Mat& img = plan.Image();

  // The path (truth, for the figure only), dashed red as in the paper.
  std::vector<cv::Point2d> pts;
  pts.reserve(run.true_path.size() / 4 + 2);
  for (std::size_t i = 0; i < run.true_path.size(); i += 4) pts.push_back(plan.ToPixel(run.true_path[i].Translation()));
  if (!run.true_path.empty()) pts.push_back(plan.ToPixel(run.true_path.back().Translation()));
  DrawDashed(img, pts, kPathBgr, 6.0);

  // Start pose.
  const cv::Point2d s = plan.ToPixel(run.start.Translation());
  cv::circle(img, s, 6, kStartBgr, 2, cv::LINE_AA);
  cv::line(img, s, s + cv::Point2d(12 * std::cos(run.start.yaw), -12 * std::sin(run.start.yaw)), kStartBgr, 2, cv::LINE_AA);

  // End detections (green asterisks) and numbered turn points.
  int turn_number = 0;
  for (const ExploreMark& m : run.marks) {
    const cv::Point2d p = plan.ToPixel(m.world_T_robot.Translation());
    switch (m.event.kind) {
      case explore::ExploreEvent::Kind::kEndDetected:
        cv::drawMarker(img, p, kEndBgr, cv::MARKER_STAR, 12, 2, cv::LINE_AA);
        break;
      case explore::ExploreEvent::Kind::kTurn: {
        ++turn_number;
        const std::string label = std::to_string(turn_number);
        cv::circle(img, p, 3, kTurnBgr, cv::FILLED, cv::LINE_AA);
        // Later visits of the same place would overprint: offset labels by their number.
        const cv::Point2d off(6 + 4 * ((turn_number - 1) % 4), -6 - 10 * (((turn_number - 1) / 4) % 3));
        cv::putText(img, label, p + off, cv::FONT_HERSHEY_SIMPLEX, 0.35, kTurnBgr, 1, cv::LINE_AA);
        break;
      }
      case explore::ExploreEvent::Kind::kStall:
        cv::drawMarker(img, p, kStallBgr, cv::MARKER_TILTED_CROSS, 10, 2, cv::LINE_AA);
        break;
      case explore::ExploreEvent::Kind::kJunction:
        // Side branches found while following: a hollow blue diamond.
        cv::drawMarker(img, p, kTurnBgr, cv::MARKER_DIAMOND, 9, 1, cv::LINE_AA);
        break;
      case explore::ExploreEvent::Kind::kScanDone: break;
    }
  }
  // Header: title and the run's figures.
  const int header = 44;
  cv::Mat out(img.rows + header, img.cols, img.type(), cv::Scalar(255, 255, 255));
  img.copyTo(out(cv::Rect(0, header, img.cols, img.rows)));
  const ExploreSummary& sm = run.summary;
  char line[256];
  std::snprintf(line, sizeof line, "%s", title.empty() ? ("squint explore: " + run.world_name).c_str() : title.c_str());
  cv::putText(out, line, {8, 17}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  std::snprintf(line, sizeof line,
                "%.1f min, %.0f m, coverage %.2f, %d ends (green *), %d turns (numbers), junctions (diamonds), %d collisions",
                sm.sim_seconds / 60.0, sm.distance_m, sm.coverage, sm.ends_detected, sm.turns, sm.collisions);
  cv::putText(out, line, {8, 36}, cv::FONT_HERSHEY_SIMPLEX, 0.42, cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
  return out;
}

std::string SummaryJson(const ExploreSummary& s) {
  nlohmann::ordered_json j;
  j["sim_seconds"] = s.sim_seconds;
  j["distance_m"] = s.distance_m;
  j["collisions"] = s.collisions;
  j["coverage"] = s.coverage;
  j["ends_detected"] = s.ends_detected;
  j["turns"] = s.turns;
  j["frames"] = s.frames;
  j["frames_fully_processed"] = s.frames_fully_processed;
  j["perception_cpu_seconds"] = s.perception_cpu_seconds;
  j["wall_seconds"] = s.wall_seconds;
  j["proceeded"] = s.proceeded;
  j["outcome"] = s.outcome;
  // Added after the other keys (null when there was nothing to measure): the start-up axis and
  // the axis while following, against ground truth.
  auto num = [](double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr); };
  j["setoff_seconds"] = num(s.setoff_seconds);
  j["setoff_axis_error_deg"] = num(s.setoff_axis_error_deg);
  j["axis_error_p90_deg"] = num(s.axis_error_p90_deg);
  j["axis_error_over_10deg"] = num(s.axis_error_over_10deg);
  // The obstacle pipeline (`--obstacle-pipeline`; zeros when off): frame pairs run and classified,
  // advices with an obstacle across the path, frames it steered or stopped, stop-and-turns.
  j["ipt_pairs"] = s.ipt_pairs;
  j["ipt_classified"] = s.ipt_classified;
  j["advice_in_path"] = s.advice_in_path;
  j["override_frames"] = s.override_frames;
  j["obstacle_stops"] = s.obstacle_stops;
  // Sonar scans that showed the robot's own reflection (`--mirror-watch`; 0 when off).
  j["mirror_scans"] = s.mirror_scans;
  j["align_line_overrides"] = s.align_line_overrides;
  // Scans whose choice of direction `--scan-entropy-floor` changed (0 when off).
  j["scan_entropy_skips"] = s.scan_entropy_skips;
  j["wall_keep_frames"] = s.wall_keep_frames;
  // Scans whose choice of direction `--scan-wall-entropy` changed (0 when off).
  j["scan_wall_entropy_skips"] = s.scan_wall_entropy_skips;
  // Contacts the robot felt from its wheels (`--feel-contacts`; 0 when off).
  j["contacts_felt"] = s.contacts_felt;
  j["near_edges"] = s.near_edges;
  // The first contact (null / empty without one): when, the robot's true position, what it
  // touched ("wall" or the world file's entry).
  j["first_collision_s"] = num(s.first_collision_s);
  j["first_collision_x_m"] = s.first_hit.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(s.first_collision_pose.x);
  j["first_collision_y_m"] = s.first_hit.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(s.first_collision_pose.y);
  j["first_hit"] = s.first_hit;
  return j.dump(2) + "\n";
}

void WriteExploreOutputs(const std::filesystem::path& dir, const sim::World& world, const ExploreRunResult& run) {
  io::WriteFileAtomically(dir / "summary.json", SummaryJson(run.summary));
  WritePng(dir / "map.png", DrawExploreMap(world, run));

  io::AtomicFile csv(dir / "trace.csv");
  std::ostream& o = csv.Stream();
  o << "t_s,true_x_m,true_y_m,true_yaw_deg,odom_x_m,odom_y_m,odom_yaw_deg,processed,heading_deg,centre_heading_deg,"
       "dist_end_m,entropy_nats,heading_est_deg,dist_est_m,true_heading_deg,true_lateral_m,true_dist_end_m,state,"
       "v_mps,omega_rps,collided,light_lateral_m,light_heading_deg,light_lateral_est_m\n";
  for (const ExploreTraceRow& r : run.trace) {
    o << Cell(r.t_s, 4) << ',' << Cell(r.world_T_robot.x, 4) << ',' << Cell(r.world_T_robot.y, 4) << ','
      << Cell(RadToDeg(r.world_T_robot.yaw), 3) << ',' << Cell(r.odom_T_robot.x, 4) << ',' << Cell(r.odom_T_robot.y, 4)
      << ',' << Cell(RadToDeg(r.odom_T_robot.yaw), 3) << ',' << (r.processed ? 1 : 0) << ',' << Cell(r.heading_deg, 3)
      << ',' << Cell(r.centre_heading_deg, 3) << ',' << Cell(r.dist_end_m, 3) << ',' << Cell(r.entropy, 4) << ','
      << Cell(r.heading_est_deg, 3) << ',' << Cell(r.dist_est_m, 3) << ',' << Cell(r.true_heading_deg, 3) << ','
      << Cell(r.true_lateral_m, 3) << ',' << Cell(r.true_dist_end_m, 3) << ',' << explore::StateName(r.state) << ','
      << Cell(r.v_mps, 3) << ',' << Cell(r.omega_rps, 3) << ',' << (r.collided ? 1 : 0) << ',' << Cell(r.light_lateral_m, 3)
      << ',' << Cell(r.light_heading_deg, 3) << ',' << Cell(r.light_lateral_est_m, 3) << '\n';
  }
  csv.Commit();

  // The explorer's events (ends, junctions, turns, stalls) with the true and odometry poses.
  io::AtomicFile ev(dir / "events.csv");
  std::ostream& e = ev.Stream();
  e << "t_s,kind,true_x_m,true_y_m,true_yaw_deg,odom_x_m,odom_y_m,node,turn_deg,note\n";
  for (const ExploreMark& m : run.marks) {
    const char* kind = "scan";
    switch (m.event.kind) {
      case explore::ExploreEvent::Kind::kScanDone: kind = "scan_done"; break;
      case explore::ExploreEvent::Kind::kEndDetected: kind = "end"; break;
      case explore::ExploreEvent::Kind::kTurn: kind = "turn"; break;
      case explore::ExploreEvent::Kind::kStall: kind = "stall"; break;
      case explore::ExploreEvent::Kind::kJunction: kind = "junction"; break;
    }
    std::string note = m.event.note;
    std::replace(note.begin(), note.end(), ',', ';');
    e << Cell(m.event.stamp_s, 2) << ',' << kind << ',' << Cell(m.world_T_robot.x, 3) << ',' << Cell(m.world_T_robot.y, 3)
      << ',' << Cell(RadToDeg(m.world_T_robot.yaw), 1) << ',' << Cell(m.event.odom_T_robot.x, 3) << ','
      << Cell(m.event.odom_T_robot.y, 3) << ',' << m.event.node << ',' << m.event.turn_deg << ",\"" << note << "\"\n";
  }
  ev.Commit();
}

}  // namespace squint::eval
