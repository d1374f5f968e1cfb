// IPT obstacle evaluation: samples from labelled sequences, ROC of D, β learning (leave-one-out),
// and the paper's Table 1 figures per sequence.
#include "squint/eval/obstacles_eval.hpp"

#include <cmath>
#include <limits>

#include "squint/core/error.hpp"
#include "squint/io/sequence.hpp"

namespace squint::eval {

using obstacles::ClassifierOptions;
using obstacles::FeatureClass;

SequenceSamples CollectObstacleSamples(const std::filesystem::path& path, const obstacles::IptOptions& options,
                                       const std::function<void(std::size_t, std::size_t)>& progress) {
  const io::Sequence seq = io::Sequence::Read(path);
  if (!seq.HasLabels()) throw Error(path.string() + ": every frame needs a label mask (frames.csv column `label`)");
  SequenceSamples out;
  out.name = seq.Info().name.empty() ? path.filename().string() : seq.Info().name;
  obstacles::IptPipeline pipeline(seq.Camera(), options);
  obstacles::PairResult result;
  cv::Mat previous = seq.Size() > 0 ? seq.LoadImage(0) : cv::Mat();
  double matches = 0.0;
  for (std::size_t i = 1; i < seq.Size(); ++i) {
    const cv::Mat current = seq.LoadImage(i);
    const cv::Mat label = seq.LoadLabel(i);
    if (label.size() != current.size())
      throw Error(path.string() + ": label mask of frame " + std::to_string(i) + " differs in size from the image");
    pipeline.Process(previous, current, seq.Frames()[i - 1].odom, seq.Frames()[i].odom, &result);
    ++out.pairs;
    matches += result.matches;
    if (!result.Ok()) {
      ++out.skipped[obstacles::PairStatusName(result.status)];
    } else {
      ++out.pairs_ok;
      for (const auto& f : result.measured) {
        const int u = std::clamp(static_cast<int>(std::lround(f.pixel.x())), 0, label.cols - 1);
        const int v = std::clamp(static_cast<int>(std::lround(f.pixel.y())), 0, label.rows - 1);
        out.samples.push_back({i, f.pixel.x(), f.pixel.y(), f.zone, f.discrepancy_m, f.signed_discrepancy_m,
                               f.plain_discrepancy_m, f.previous_pixel.x(), f.previous_pixel.y(), f.motion_epipolar_px,
                               label.at<unsigned char>(v, u) != 0});
      }
    }
    previous = current;
    if (progress) progress(i, seq.Size() - 1);
  }
  out.mean_matches = out.pairs > 0 ? matches / static_cast<double>(out.pairs) : 0.0;
  return out;
}

std::vector<ScoredLabel> DiscrepancyScores(const std::vector<ObstacleSample>& samples, bool below_horizon_only) {
  std::vector<ScoredLabel> scores;
  scores.reserve(samples.size());
  for (const auto& s : samples) {
    if (!s.discrepancy_m) {
      if (below_horizon_only) continue;
      scores.push_back({std::numeric_limits<double>::infinity(), s.obstacle});
    } else {
      scores.push_back({*s.discrepancy_m, s.obstacle});
    }
  }
  return scores;
}

namespace {
// As DiscrepancyScores(samples, false), for the paper's D (eq. 4).
std::vector<ScoredLabel> PlainDiscrepancyScores(const std::vector<ObstacleSample>& samples) {
  std::vector<ScoredLabel> scores;
  scores.reserve(samples.size());
  for (const auto& s : samples)
    scores.push_back({s.plain_discrepancy_m.value_or(std::numeric_limits<double>::infinity()), s.obstacle});
  return scores;
}
}  // namespace

std::vector<obstacles::LabelledDiscrepancy> TrainingSamples(const std::vector<ObstacleSample>& samples) {
  std::vector<obstacles::LabelledDiscrepancy> out;
  for (const auto& s : samples)
    if (s.discrepancy_m && s.zone < obstacles::kHorizonZone) out.push_back({s.zone, *s.discrepancy_m, s.obstacle});
  return out;
}

ClassifierScore ScoreClassifier(const std::vector<ObstacleSample>& samples, std::size_t pairs_ok,
                                const ClassifierOptions& classifier) {
  ClassifierScore score;
  score.features = samples.size();
  for (const auto& s : samples) {
    const auto cls = obstacles::ClassifyFeature(s.zone, s.discrepancy_m, classifier);
    if (!cls) continue;
    ++score.classified;
    const bool predicted = *cls == FeatureClass::kObstacle;
    if (s.obstacle) (predicted ? score.confusion.tp : score.confusion.fn) += 1;
    else (predicted ? score.confusion.fp : score.confusion.tn) += 1;
  }
  score.fp_per_feature = score.features > 0 ? static_cast<double>(score.confusion.fp) / score.features : 0.0;
  score.classified_per_pair = pairs_ok > 0 ? static_cast<double>(score.classified) / pairs_ok : 0.0;
  return score;
}

namespace {

ClassifierOptions SingleBeta(const ClassifierOptions& base, double beta) {
  ClassifierOptions c = base;
  c.zone_beta = false;
  c.refinement = false;
  c.zones[0].beta_m = beta;
  return c;
}

void Accumulate(ClassifierScore& total, const ClassifierScore& s, std::size_t pairs_ok, std::size_t& total_pairs) {
  total.confusion += s.confusion;
  total.features += s.features;
  total.classified += s.classified;
  total_pairs += pairs_ok;
  total.fp_per_feature = total.features > 0 ? static_cast<double>(total.confusion.fp) / total.features : 0.0;
  total.classified_per_pair = total_pairs > 0 ? static_cast<double>(total.classified) / total_pairs : 0.0;
}

}  // namespace

ObstacleEvalReport EvaluateObstacles(const std::vector<SequenceSamples>& sequences,
                                     const obstacles::IptOptions& options, const ObstacleEvalOptions& eval_options) {
  ObstacleEvalReport report;
  const double delta = eval_options.learning.delta;
  std::vector<ObstacleSample> all;
  for (const auto& s : sequences) all.insert(all.end(), s.samples.begin(), s.samples.end());
  const auto all_training = TrainingSamples(all);
  report.optimum_beta_m = obstacles::OptimalBeta(all_training, delta).value_or(options.classifier.zones[0].beta_m);
  report.pooled_roc = ComputeRoc(DiscrepancyScores(all, false));
  report.pooled_auc_below_horizon = ComputeRoc(DiscrepancyScores(all, true)).auc;
  report.pooled_at_optimum = ConfusionAt(DiscrepancyScores(all, false), report.optimum_beta_m);
  report.zone_classifier_all =
      obstacles::LearnZoneThresholds(all_training, eval_options.learning, options.classifier);
  report.leave_one_out = eval_options.leave_one_out && sequences.size() > 1;

  std::size_t single_pairs = 0, zone_pairs = 0;
  double auc_sum = 0.0, auc_plain_sum = 0.0;
  for (std::size_t k = 0; k < sequences.size(); ++k) {
    const SequenceSamples& seq = sequences[k];
    SequenceReport r;
    r.name = seq.name;
    r.pairs = seq.pairs;
    r.pairs_ok = seq.pairs_ok;
    r.features = seq.samples.size();
    r.skipped = seq.skipped;
    r.roc = ComputeRoc(DiscrepancyScores(seq.samples, false));
    r.auc = r.roc.auc;
    r.auc_below_horizon = ComputeRoc(DiscrepancyScores(seq.samples, true)).auc;
    r.auc_plain = ComputeRoc(PlainDiscrepancyScores(seq.samples)).auc;
    auc_sum += r.auc;
    auc_plain_sum += r.auc_plain;
    std::vector<obstacles::LabelledDiscrepancy> training;
    if (report.leave_one_out) {
      for (std::size_t j = 0; j < sequences.size(); ++j)
        if (j != k) {
          const auto t = TrainingSamples(sequences[j].samples);
          training.insert(training.end(), t.begin(), t.end());
        }
    } else {
      training = all_training;
    }
    r.single_beta_m = obstacles::OptimalBeta(training, delta).value_or(options.classifier.zones[0].beta_m);
    r.single = ScoreClassifier(seq.samples, seq.pairs_ok, SingleBeta(options.classifier, r.single_beta_m));
    r.zone_classifier = obstacles::LearnZoneThresholds(training, eval_options.learning, options.classifier);
    r.zone_classifier.zone_beta = true;
    r.zone_classifier.refinement = true;
    r.zone = ScoreClassifier(seq.samples, seq.pairs_ok, r.zone_classifier);
    Accumulate(report.pooled_single, r.single, seq.pairs_ok, single_pairs);
    Accumulate(report.pooled_zone, r.zone, seq.pairs_ok, zone_pairs);
    report.sequences.push_back(std::move(r));
  }
  report.mean_auc = sequences.empty() ? 0.0 : auc_sum / static_cast<double>(sequences.size());
  report.mean_auc_plain = sequences.empty() ? 0.0 : auc_plain_sum / static_cast<double>(sequences.size());
  return report;
}

}  // namespace squint::eval
