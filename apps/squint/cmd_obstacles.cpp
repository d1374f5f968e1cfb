// `squint obstacles SEQUENCE [--options FILE] [--detector sift|orb|akaze|klt] --out features.csv`:
// IPT obstacle detection on every consecutive frame pair, one CSV row per classified feature.
#include <filesystem>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "squint/config/obstacles_yaml.hpp"
#include "squint/core/error.hpp"
#include "squint/io/atomic_output.hpp"
#include "squint/io/sequence.hpp"
#include "squint/obstacles/ipt_pipeline.hpp"

namespace squint::app {
namespace {

struct ObstaclesCommandOptions {
  std::string sequence;
  std::string options_file;
  std::string detector;
  std::string out;
};

// The fixed columns, then the match in the earlier frame, the image zone (0–3) and the paper's D
// (eq. 4); discrepancy_m is the one classified (the mirror-aware discrepancy by default).
constexpr const char* kHeader = "frame,u,v,discrepancy_m,class,previous_u,previous_v,zone,plain_discrepancy_m";

void Run(const ObstaclesCommandOptions& cli) {
  obstacles::IptOptions options;
  if (!cli.options_file.empty()) options = config::LoadIptOptions(cli.options_file);
  if (!cli.detector.empty() && !obstacles::ParseDetector(cli.detector, &options.features.detector))
    throw Error("--detector must be sift, orb, akaze or klt (got '" + cli.detector + "')");
  const io::Sequence seq = io::Sequence::Read(cli.sequence);
  obstacles::IptPipeline pipeline(seq.Camera(), options);
  io::AtomicFile out(cli.out);
  std::ostream& os = out.Stream();
  os << kHeader << '\n';
  ProgressBar bar("obstacles", seq.Size() > 1 ? seq.Size() - 1 : 0);
  obstacles::PairResult result;
  std::size_t ok = 0, features = 0;
  cv::Mat previous = seq.Size() > 0 ? seq.LoadImage(0) : cv::Mat();
  for (std::size_t i = 1; i < seq.Size(); ++i) {
    const cv::Mat current = seq.LoadImage(i);
    pipeline.Process(previous, current, seq.Frames()[i - 1].odom, seq.Frames()[i].odom, &result);
    if (!result.Ok()) {
      // Once per skipped pair, with the reason.
      spdlog::warn("obstacles: frames {}-{}: {} ({})", i - 1, i, result.reason, obstacles::PairStatusName(result.status));
    } else {
      ++ok;
      for (const auto& f : result.measured) {
        if (!f.cls) continue;  // left unclassified by the refinement filter
        ++features;
        os << i << ',' << fmt::format("{:.2f},{:.2f},", f.pixel.x(), f.pixel.y());
        if (f.discrepancy_m) os << fmt::format("{:.5f}", *f.discrepancy_m);
        os << ',' << (*f.cls == obstacles::FeatureClass::kObstacle ? "obstacle" : "ground") << ','
           << fmt::format("{:.2f},{:.2f},{},", f.previous_pixel.x(), f.previous_pixel.y(), f.zone);
        if (f.plain_discrepancy_m) os << fmt::format("{:.5f}", *f.plain_discrepancy_m);
        os << '\n';
      }
    }
    previous = current;
    bar.Update(i);
  }
  bar.Finish();
  out.Commit();
  const std::size_t pairs = seq.Size() > 1 ? seq.Size() - 1 : 0;
  spdlog::info("obstacles: {} of {} pairs classified, {} features ({:.1f} per classified pair) -> {}", ok, pairs,
               features, ok ? static_cast<double>(features) / ok : 0.0, cli.out);
}

void Register(CLI::App& root) {
  auto opt = std::make_shared<ObstaclesCommandOptions>();
  CLI::App* cmd = root.add_subcommand("obstacles", "Classify tracked features as ground or obstacle (inverse perspective)");
  cmd->add_option("SEQUENCE", opt->sequence, "Sequence folder (with odometry)")->required();
  cmd->add_option("--options", opt->options_file, "Options YAML (e.g. the one `squint eval obstacles` writes)");
  cmd->add_option("--detector", opt->detector, "Feature detector: sift (default), orb, akaze or klt");
  cmd->add_option("--out", opt->out, "Output CSV: frame,u,v,discrepancy_m,class,...")->required();
  cmd->callback([opt] { Run(*opt); });
}

const CommandRegistrar kRegistrar(310, &Register);

}  // namespace
}  // namespace squint::app
