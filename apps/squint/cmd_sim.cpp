// `squint sim ...`: the simulator's commands: record a protocol into a sequence folder, render
// one view, draw a floor plan, list the built-in worlds, and draw a contact sheet of worlds.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "command.hpp"
#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/io/atomic_output.hpp"
#include "squint/io/sequence.hpp"
#include "squint/sim/floor_plan.hpp"
#include "squint/sim/ground_truth.hpp"
#include "squint/sim/protocols.hpp"
#include "squint/sim/renderer.hpp"
#include "squint/sim/robot.hpp"
#include "squint/sim/world.hpp"

namespace squint::app {
namespace {

namespace fs = std::filesystem;

struct CameraFlags {
  int width = 0;   // 0 = the world's
  int height = 0;
  sim::RenderOptions render;  // its member initialisers are the defaults
};

void AddCameraFlags(CLI::App* cmd, CameraFlags& f) {
  cmd->add_option("--width", f.width, "Image width (default: the world's camera; the field of view is kept)")
      ->check(CLI::Range(1, 8192));
  cmd->add_option("--height", f.height, "Image height (default: the world's camera)")->check(CLI::Range(1, 8192));
  cmd->add_option("--supersample", f.render.supersample, "n: n×n samples per pixel")->check(CLI::Range(1, 16))->capture_default_str();
  cmd->add_option("--noise", f.render.noise_sigma, "Sensor noise, grey levels (standard deviation)")
      ->check(CLI::Range(0.0, 100.0))->capture_default_str();
  cmd->add_option("--exposure", f.render.exposure, "Exposure factor")->check(CLI::Range(0.01, 100.0))->capture_default_str();
  cmd->add_option("--seed", f.render.seed, "Noise and odometry seed")->capture_default_str();
}

CameraModel CameraFor(const sim::World& world, const CameraFlags& f) {
  sim::CameraMount mount = world.camera;
  if (f.width > 0) mount.width = f.width;
  if (f.height > 0) mount.height = f.height;
  if (f.width > 0 && f.height == 0) mount.height = std::max(1, static_cast<int>(std::lround(f.width * 0.75)));
  return mount.Model();
}

sim::RenderOptions RenderFor(const CameraFlags& f) { return f.render; }

void WriteImage(const std::string& path, const cv::Mat& image) {
  std::vector<uchar> buf;
  const std::string ext = fs::path(path).extension().string();
  if (ext.empty() || !cv::imencode(ext, image, buf))
    throw Error(path + ": cannot encode an image with this extension (use .png)");
  io::WriteFileAtomically(path, std::string(buf.begin(), buf.end()));
}

// ---- record ----------------------------------------------------------------------------------
struct RecordOptions {
  std::string world;
  std::string protocol;
  std::string out;
  int corridor = 0;
  bool labels = false;
  sim::OdometryOptions odometry;  // its member initialisers are the defaults
  CameraFlags camera;
};

void Record(const RecordOptions& o) {
  const sim::World world = sim::LoadWorld(o.world);
  std::vector<sim::TimedPose> schedule;
  double rate = 0;
  CameraFlags cam = o.camera;
  bool labels = o.labels;
  if (o.protocol == "sweep") {
    sim::SweepOptions s;
    s.corridor = o.corridor;
    schedule = sim::SweepSchedule(world, s);
    rate = s.rate_hz;
  } else if (o.protocol == "drive") {
    sim::DriveOptions d;
    d.corridor = o.corridor;
    schedule = sim::DriveSchedule(world, d);
    rate = d.rate_hz;
  } else if (o.protocol == "creep") {
    sim::CreepOptions c;
    c.corridor = o.corridor;
    schedule = sim::CreepSchedule(world, c);
    rate = 1.0 / c.period_s;
    if (cam.width == 0) cam.width = 256, cam.height = 192;
    labels = true;
  } else {
    throw Error("sim record: --protocol must be sweep, drive or creep (got '" + o.protocol + "')");
  }
  const CameraModel camera = CameraFor(world, cam);
  sim::Renderer renderer(world, camera, RenderFor(cam));
  sim::OdometryOptions odo = o.odometry;
  odo.seed = cam.render.seed;
  if (const std::string why = odo.Validate(); !why.empty()) throw Error("sim record: " + why);
  sim::Odometry odometry(odo);
  const std::string out = o.out.empty() ? fmt::format("{}-{}", world.name, o.protocol) : o.out;
  io::SequenceInfo info;
  info.name = fmt::format("{} {} (squint sim)", world.name, o.protocol);
  info.camera = camera;
  info.frame_rate_hz = rate;
  io::SequenceWriter writer(out, info);
  ProgressBar progress("sim record", schedule.size());
  cv::Mat image(camera.height, camera.width, CV_8UC1), label(camera.height, camera.width, CV_8UC1);
  for (std::size_t i = 0; i < schedule.size(); ++i) {
    const sim::TimedPose& tp = schedule[i];
    renderer.Render(tp.pose, {image.data, image.cols, image.rows, static_cast<std::ptrdiff_t>(image.step)},
                    labels ? label.data : nullptr, static_cast<std::ptrdiff_t>(label.step), nullptr, 0, i);
    io::FrameRecord rec;
    rec.stamp = tp.stamp;
    rec.odom = i == 0 ? (odometry.Reset(tp.pose), odometry.Pose()) : odometry.Update(tp.pose);
    rec.gt = sim::GroundTruthAt(world, tp.pose);
    writer.Add(rec, image, labels ? label : cv::Mat());
    progress.Update(i + 1);
  }
  writer.Finish();
  progress.Finish();
  std::cout << fmt::format("wrote {} frames ({}x{}, {}) to {}\n", schedule.size(), camera.width, camera.height, o.protocol, out);
}

// ---- render ----------------------------------------------------------------------------------
struct RenderCmdOptions {
  std::string world;
  std::string pose;
  std::string out;
  std::string label_out;
  CameraFlags camera;
};

Pose2 ParsePose(const std::string& text, const sim::World& world) {
  if (text.empty()) return world.start;
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw Error("--pose: '" + text + "' is not X,Y,YAW_DEG (metres, metres, degrees)");
    }
  }
  if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
    throw Error("--pose: '" + text + "' is not X,Y,YAW_DEG (metres, metres, degrees)");
  return {v[0], v[1], DegToRad(v[2])};
}

void RenderCmd(const RenderCmdOptions& o) {
  const sim::World world = sim::LoadWorld(o.world);
  const Pose2 pose = ParsePose(o.pose, world);
  if (!world.IsFree(pose.Translation()))
    throw Error(fmt::format("--pose: ({:.2f}, {:.2f}) is outside the floor of {}", pose.x, pose.y, world.source));
  sim::Renderer renderer(world, CameraFor(world, o.camera), RenderFor(o.camera));
  cv::Mat label;
  const cv::Mat image = renderer.Render(pose, o.label_out.empty() ? nullptr : &label);
  WriteImage(o.out, image);
  if (!o.label_out.empty()) WriteImage(o.label_out, label);
  const GroundTruth gt = sim::GroundTruthAt(world, pose);
  std::cout << fmt::format("wrote {} ({}x{}); heading {:.2f} deg, lateral {:.3f} m, dist_end {:.3f} m\n", o.out, image.cols,
                           image.rows, gt.heading_deg.value_or(NAN), gt.lateral_m.value_or(NAN), gt.dist_end_m.value_or(NAN));
}

// ---- map ---------------------------------------------------------------------------------------
struct MapOptions {
  std::string world;
  std::string out;
  double px_per_m = 20;
};

void MapCmd(const MapOptions& o) {
  const sim::World world = sim::LoadWorld(o.world);
  sim::FloorPlanOptions fo;
  fo.px_per_m = o.px_per_m;
  sim::FloorPlan plan(world, fo);
  WriteImage(o.out, plan.Image());
  std::cout << fmt::format("wrote {} ({}x{}); {} corridors, {:.1f} m of corridor, {} walls, {} lights, {} obstacle primitives\n",
                           o.out, plan.Image().cols, plan.Image().rows, world.corridors.size(), world.CorridorLength(),
                           world.walls.size(), world.lights.size(), world.obstacles.size());
}

// ---- sheet -------------------------------------------------------------------------------------
struct SheetOptions {
  std::vector<std::string> worlds;
  std::string out;
  int width = 32, height = 24;
  int scale = 0;  // display upscaling; 0 = to about 256 px wide
  CameraFlags camera;
};

void SheetCmd(const SheetOptions& o) {
  std::vector<std::string> names = o.worlds;
  if (names.empty())
    for (const std::string& n : sim::BuiltinWorldNames())
      if (n.rfind("corridor-", 0) == 0) names.push_back(n);
  const int scale = o.scale > 0 ? o.scale : std::max(1, 256 / o.width);
  const int cols = 5, cell_w = o.width * scale, cell_h = o.height * scale, label_h = 18;
  const int rows = (static_cast<int>(names.size()) + cols - 1) / cols;
  cv::Mat sheet(rows * (cell_h + label_h + 4), cols * (cell_w + 4), CV_8UC1, cv::Scalar(255));
  for (std::size_t i = 0; i < names.size(); ++i) {
    const sim::World world = sim::LoadWorld(names[i]);
    CameraFlags cam = o.camera;
    cam.width = o.width;
    cam.height = o.height;
    sim::Renderer renderer(world, CameraFor(world, cam), RenderFor(cam));
    const cv::Mat img = renderer.Render(world.start);
    cv::Mat big;
    cv::resize(img, big, cv::Size(cell_w, cell_h), 0, 0, cv::INTER_NEAREST);
    const int x = static_cast<int>(i % cols) * (cell_w + 4), y = static_cast<int>(i / cols) * (cell_h + label_h + 4);
    big.copyTo(sheet(cv::Rect(x, y + label_h, cell_w, cell_h)));
    cv::putText(sheet, world.name, cv::Point(x + 2, y + 13), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0), 1, cv::LINE_AA);
  }
  WriteImage(o.out, sheet);
  std::cout << fmt::format("wrote {} ({} worlds at {}x{})\n", o.out, names.size(), o.width, o.height);
}

void Register(CLI::App& root) {
  CLI::App* sim = GetOrAddSubcommand(root, "sim", "The simulator: built-in and YAML worlds, rendering, protocols");
  sim->require_subcommand(1);

  auto rec = std::make_shared<RecordOptions>();
  CLI::App* r = sim->add_subcommand("record", "Record a paper protocol into a sequence folder (SEQUENCE_FORMAT.md)");
  r->add_option("WORLD", rec->world, "Built-in world name or world YAML file")->required();
  r->add_option("--protocol", rec->protocol,
                "sweep: rotate -20..+20 deg in 1 deg steps every 4.5 m (0.5 Hz); drive: centre and 0.45 m each "
                "side at 0.4 m/s, 30 Hz; creep: 31 mm steps around the obstacles, 256x192, label masks")
      ->required();
  r->add_option("--out", rec->out, "Output sequence folder (default WORLD-PROTOCOL)");
  r->add_option("--corridor", rec->corridor, "Index of the corridor to record in (world order)");
  r->add_flag("--labels", rec->labels, "Write label masks (always on for creep)");
  r->add_option("--odom-trans-noise", rec->odometry.trans_noise_frac, "Odometry distance error, fraction of distance")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  r->add_option("--odom-rot-noise", rec->odometry.rot_noise_frac, "Odometry yaw error, fraction of the turn")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  r->add_option("--odom-drift", rec->odometry.drift_rad_per_m, "Odometry yaw drift, rad per metre (left positive)")
      ->capture_default_str();
  AddCameraFlags(r, rec->camera);
  r->callback([rec] { Record(*rec); });

  auto ren = std::make_shared<RenderCmdOptions>();
  CLI::App* rn = sim->add_subcommand("render", "Render one view of a world");
  rn->add_option("WORLD", ren->world, "Built-in world name or world YAML file")->required();
  rn->add_option("--pose", ren->pose, "X,Y,YAW_DEG (default: the world's start)");
  rn->add_option("--out", ren->out, "Output PNG")->required();
  rn->add_option("--label-out", ren->label_out, "Also write the label mask (0 floor, 255 standing)");
  AddCameraFlags(rn, ren->camera);
  rn->callback([ren] { RenderCmd(*ren); });

  auto map = std::make_shared<MapOptions>();
  CLI::App* m = sim->add_subcommand("map", "Draw a world's floor plan");
  m->add_option("WORLD", map->world, "Built-in world name or world YAML file")->required();
  m->add_option("--out", map->out, "Output PNG")->required();
  m->add_option("--px-per-m", map->px_per_m, "Scale")->check(CLI::Range(1.0, 500.0));
  m->callback([map] { MapCmd(*map); });

  CLI::App* l = sim->add_subcommand("list", "List the built-in worlds");
  l->callback([] {
    for (const std::string& n : sim::BuiltinWorldNames()) {
      const sim::World w = sim::LoadWorld(n);
      std::cout << fmt::format("{:<16} {:>2} corridors {:>6.1f} m  {:>3} lights  {:>3} obstacle primitives\n", n,
                               w.corridors.size(), w.CorridorLength(), w.lights.size(), w.obstacles.size());
    }
  });

  auto sh = std::make_shared<SheetOptions>();
  CLI::App* s = sim->add_subcommand("sheet", "Contact sheet of worlds seen from their start (default: corridor-*)");
  s->add_option("WORLDS", sh->worlds, "Worlds (default: every built-in corridor-*)");
  s->add_option("--out", sh->out, "Output PNG")->required();
  s->add_option("--width", sh->width, "Image width")->check(CLI::Range(4, 4096));
  s->add_option("--height", sh->height, "Image height")->check(CLI::Range(3, 4096));
  s->add_option("--scale", sh->scale, "Display upscaling (nearest neighbour)")->check(CLI::Range(1, 64));
  s->add_option("--supersample", sh->camera.render.supersample, "n: n×n samples per pixel")->check(CLI::Range(1, 16));
  s->add_option("--noise", sh->camera.render.noise_sigma, "Sensor noise, grey levels")->check(CLI::Range(0.0, 100.0));
  s->callback([sh] { SheetCmd(*sh); });
}

const CommandRegistrar kRegistrar(600, &Register);

}  // namespace
}  // namespace squint::app
