// `squint perceive INPUT [--calib FILE] [--no-gate] [--out FILE]`: corridor perception on every
// frame of a sequence folder, image folder or video, written as one CSV row per frame.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "command.hpp"
#include "squint/config/corridor_yaml.hpp"
#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/core/pose.hpp"
#include "squint/corridor/perceiver.hpp"
#include "squint/io/atomic_output.hpp"
#include "squint/io/frame_source.hpp"

namespace squint::app {
namespace {

namespace fs = std::filesystem;

struct PerceiveOptions {
  std::string input;
  std::string calib;
  std::string out;
  bool no_gate = false;
};

// The fixed header of the issue, then extra columns: the gate's entropy change, the ground
// truth when the input has it (for evaluation), and each measure's reason when it gave none.
constexpr const char* kHeader =
    "stamp,processed,heading_deg,dist_end_m,heading_entropy_deg,heading_symmetry_deg,heading_phase_deg,"
    "heading_vanishing_deg,heading_bright_deg,dist_ttc_m,dist_jeffrey_m,dist_entropy_m,"
    "gate_change,gt_heading_deg,gt_dist_end_m,heading_reasons,distance_reasons,heading_instant_deg,dist_floor_m";

std::string Cell(const std::optional<double>& v, int decimals) {
  if (!v || !std::isfinite(*v)) return {};
  return fmt::format("{:.{}f}", *v, decimals);
}

void WriteRow(std::ostream& os, const io::Frame& frame, const corridor::PerceptionResult& r) {
  os << fmt::format("{}", frame.stamp) << ',' << (r.processed ? 1 : 0) << ',' << Cell(r.heading_deg, 3) << ','
     << Cell(r.dist_end_m, 3);
  for (const auto& h : r.heading) os << ',' << Cell(h.heading_deg, 3);
  for (const auto& d : r.distance) os << ',' << Cell(d.dist_m, 3);
  os << ',' << Cell(r.gate_change, 5) << ',' << Cell(frame.gt.heading_deg, 3) << ',' << Cell(frame.gt.dist_end_m, 3);
  // Reasons as "cue:reason" joined by ';' (empty when every cue answered or nothing ran).
  std::string reasons;
  if (r.processed) {
    for (const auto& h : r.heading) {
      if (h.HasEstimate()) continue;
      if (!reasons.empty()) reasons += ';';
      reasons += std::string(corridor::CueName(h.cue)) + ':' + corridor::ReasonText(h.reason);
    }
  }
  os << ',' << reasons;
  reasons.clear();
  if (r.processed) {
    for (const auto& d : r.distance) {
      if (d.HasEstimate()) continue;
      if (!reasons.empty()) reasons += ';';
      reasons += std::string(corridor::CueName(d.cue)) + ':' + corridor::ReasonText(d.reason);
    }
  }
  os << ',' << reasons << ',' << Cell(r.heading_instant_deg, 3) << ',' << Cell(r.dist_floor_m, 3) << '\n';
}

void Run(const PerceiveOptions& opt) {
  corridor::CorridorOptions options;
  if (!opt.calib.empty()) options = config::LoadCorridorOptions(opt.calib);
  if (opt.no_gate) options.gate.enabled = false;
  // Open the input first, so a bad input fails before anything is written.
  std::unique_ptr<io::FrameSource> source = io::OpenFrameSource(opt.input);
  corridor::Perceiver perceiver(options, source->Camera());
  std::ostringstream csv;
  csv << kHeader << '\n';
  ProgressBar progress("perceive", source->Count().value_or(0));
  std::optional<io::Frame> previous;
  std::size_t n = 0;
  while (std::optional<io::Frame> frame = source->Next()) {
    const cv::Mat& img = frame->image;
    if (img.empty() || img.depth() != CV_8U || (img.channels() != 1 && img.channels() != 3 && img.channels() != 4))
      throw Error(source->Describe() + ": frame " + std::to_string(frame->index) + " is not an 8-bit grey or colour image");
    const corridor::PixelView view{img.data, img.cols, img.rows, static_cast<std::ptrdiff_t>(img.step[0]),
                                   img.channels()};
    std::optional<double> travelled_m, turned_deg;
    double dt_s = 0.0;
    if (previous) {
      dt_s = std::max(0.0, frame->stamp - previous->stamp);
      if (previous->odom && frame->odom) {
        const Pose2 motion = Between(*previous->odom, *frame->odom);
        travelled_m = std::hypot(motion.x, motion.y);
        turned_deg = RadToDeg(WrapPi(motion.yaw));
      }
    }
    const corridor::PerceptionResult r = perceiver.Process(view, travelled_m, dt_s, turned_deg);
    WriteRow(csv, *frame, r);
    previous = std::move(frame);
    progress.Update(++n);
  }
  progress.Finish();
  if (n == 0) throw Error(source->Describe() + ": no frames");
  if (opt.out.empty()) {
    std::cout << csv.str();
    std::cout.flush();
    return;
  }
  io::AtomicFile file(opt.out);
  file.Stream() << csv.str();
  file.Commit();
}

void Register(CLI::App& root) {
  auto opt = std::make_shared<PerceiveOptions>();
  CLI::App* cmd = root.add_subcommand(
      "perceive",
      "Corridor perception (heading and distance to the end) on every frame of INPUT, as CSV.\n"
      "Columns: stamp,processed,heading_deg,dist_end_m, the five heading cues (entropy, symmetry,\n"
      "phase, vanishing, bright; deg, left positive), the three distance cues (ttc, jeffrey,\n"
      "entropy; m), then extras: gate_change, gt_heading_deg, gt_dist_end_m (ground truth when the\n"
      "input has it), heading_reasons, distance_reasons (why a cue gave no estimate), heading_instant_deg\n"
      "(the per-frame fusion; heading_deg is the heading filter's state when the options enable it),\n"
      "dist_floor_m (where the end wall stands on the floor, from the full frame and the camera's height\n"
      "and pitch; a sequence folder's camera only).\n"
      "An empty cell means no estimate; processed is 0 where the rapid-perception gate skipped the frame.");
  cmd->add_option("INPUT", opt->input, "Sequence folder, image folder or video file")->required();
  cmd->add_option("--calib", opt->calib, "Corridor options YAML (see include/squint/config/corridor_yaml.hpp)");
  cmd->add_flag("--no-gate", opt->no_gate, "Process every frame (disable rapid perception)");
  cmd->add_option("--out", opt->out,
                  "Output CSV file, written whole or not at all (default: the CSV goes to standard output "
                  "once every frame is done)");
  cmd->callback([opt] { Run(*opt); });
}

const CommandRegistrar kRegistrar(200, &Register);

}  // namespace
}  // namespace squint::app
