// `squint avoid SEQUENCE [--options FILE] --out DIR`: IPT obstacle detection, obstacle outlines,
// contact points, the polar occupancy map and free-gap steering on every consecutive frame pair.
// Writes DIR/polar.csv, DIR/steering.csv and DIR/overlays/NNNNNN.png (obstacle paper Figs 12–15).
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "squint/config/avoid_yaml.hpp"
#include "squint/core/error.hpp"
#include "squint/eval/avoid_eval.hpp"
#include "squint/eval/plot.hpp"
#include "squint/io/atomic_output.hpp"
#include "squint/io/sequence.hpp"
#include "squint/obstacles/avoid_overlay.hpp"

namespace squint::app {
namespace {

struct AvoidCommandOptions {
  std::string sequence;
  std::string options_file;
  std::string out;
  bool no_overlays = false;
};

void Run(const AvoidCommandOptions& cli) {
  const config::AvoidFileOptions options =
      cli.options_file.empty() ? config::AvoidFileOptions{} : config::LoadAvoidFileOptions(cli.options_file);
  const io::Sequence seq = io::Sequence::Read(cli.sequence);
  if (!seq.HasOdometry()) throw Error(cli.sequence + ": frames.csv needs odom_x, odom_y and odom_yaw on every row");
  io::StagedDirectory staged(cli.out);
  const std::filesystem::path dir = staged.Path();
  if (!cli.no_overlays) std::filesystem::create_directories(dir / "overlays");
  std::ofstream polar(dir / "polar.csv"), steering(dir / "steering.csv");
  if (!polar || !steering) throw Error(cli.out + ": cannot write into the staging folder " + dir.string());
  polar << "frame,bearing_deg,range_m\n";
  steering << "frame,steer_deg,stop\n";
  ProgressBar bar("avoid", seq.Size() > 1 ? seq.Size() - 1 : 0);
  std::size_t frames = 0, stops = 0;
  eval::RunAvoidOnSequence(
      seq, options,
      [&](std::size_t i, const cv::Mat& image, const obstacles::PairResult& pair, const obstacles::AvoidResult& r) {
        ++frames;
        for (const obstacles::PolarSector& s : r.map->sectors) {
          polar << i << ',' << fmt::format("{:.2f}", s.centre_deg) << ',';
          if (s.range_m) polar << fmt::format("{:.3f}", *s.range_m);
          polar << '\n';
        }
        steering << i << ',';
        if (r.decision.steer_deg) steering << fmt::format("{:.2f}", *r.decision.steer_deg);
        steering << ',' << (r.decision.stop ? 1 : 0) << '\n';
        stops += r.decision.stop;
        if (!cli.no_overlays)
          eval::WritePng(dir / "overlays" / fmt::format("{:06d}.png", i),
                         obstacles::DrawAvoidOverlay(image, pair.features, r));
        bar.Update(i);
      },
      [&](std::size_t i, const obstacles::PairResult& pair) {
        spdlog::warn("avoid: frames {}-{}: {} ({})", i - 1, i, pair.reason, obstacles::PairStatusName(pair.status));
        bar.Update(i);
      });
  bar.Finish();
  polar.close();
  steering.close();
  if (!polar || !steering) throw Error(cli.out + ": writing polar.csv or steering.csv failed");
  staged.Commit();
  spdlog::info("avoid: {} of {} pairs processed, {} stops -> {}", frames, seq.Size() > 1 ? seq.Size() - 1 : 0, stops,
               cli.out);
}

void Register(CLI::App& root) {
  auto opt = std::make_shared<AvoidCommandOptions>();
  CLI::App* cmd = root.add_subcommand(
      "avoid", "Obstacle outlines, the polar occupancy map and free-gap steering on every frame pair");
  cmd->add_option("SEQUENCE", opt->sequence, "Sequence folder (with odometry)")->required();
  cmd->add_option("--options", opt->options_file, "Options YAML with sections `ipt:` and/or `avoid:`");
  cmd->add_option("--out", opt->out, "Output folder: polar.csv, steering.csv, overlays/")->required();
  cmd->add_flag("--no-overlays", opt->no_overlays, "Skip the per-frame PNG overlays");
  cmd->callback([opt] { Run(*opt); });
}

const CommandRegistrar kRegistrar(320, &Register);

}  // namespace
}  // namespace squint::app
