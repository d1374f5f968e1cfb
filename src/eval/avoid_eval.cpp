// Evaluation of the avoidance stage against label-mask floor contacts (issue 6).
#include "squint/eval/avoid_eval.hpp"

#include <cmath>

#include "squint/core/error.hpp"

namespace squint::eval {

using obstacles::ContactPoint;
using obstacles::SectorState;

std::vector<ContactPoint> LabelContacts(const CameraModel& camera, const cv::Mat& label) {
  SQUINT_ENSURE(label.type() == CV_8UC1, "LabelContacts needs an 8-bit mask");
  std::vector<ContactPoint> out;
  for (int u = 0; u < label.cols; ++u) {
    for (int v = label.rows - 1; v >= 0; --v) {
      if (label.at<std::uint8_t>(v, u) == 0) continue;
      if (auto c = obstacles::ContactFromPixel(camera, Eigen::Vector2d(u, v + 0.5))) out.push_back(*c);
      break;
    }
  }
  return out;
}

void RunAvoidOnSequence(
    const io::Sequence& seq, const config::AvoidFileOptions& options,
    const std::function<void(std::size_t, const cv::Mat&, const obstacles::PairResult&, const obstacles::AvoidResult&)>&
        on_frame,
    const std::function<void(std::size_t, const obstacles::PairResult&)>& on_skip) {
  obstacles::IptPipeline ipt(seq.Camera(), options.ipt);
  obstacles::Avoider avoider(seq.Camera(), options.avoid);
  obstacles::PairResult pair;
  cv::Mat previous = seq.Size() > 0 ? seq.LoadImage(0) : cv::Mat();
  for (std::size_t i = 1; i < seq.Size(); ++i) {
    cv::Mat current = seq.LoadImage(i);
    ipt.Process(previous, current, seq.Frames()[i - 1].odom, seq.Frames()[i].odom, &pair);
    if (pair.Ok()) {
      const obstacles::AvoidResult& r = avoider.Process(current, pair.features);
      on_frame(i, current, pair, r);
    } else if (on_skip) {
      on_skip(i, pair);
    }
    previous = current;
  }
}

AvoidSequenceScore EvaluateAvoidSequence(const std::filesystem::path& path, const config::AvoidFileOptions& options,
                                         const AvoidEvalOptions& eval_options,
                                         const std::function<void(std::size_t, std::size_t)>& progress) {
  const io::Sequence seq = io::Sequence::Read(path);
  if (!seq.HasLabels()) throw Error(path.string() + ": every frame needs a label mask to evaluate avoidance");
  if (!seq.HasOdometry()) throw Error(path.string() + ": every frame needs odometry to evaluate avoidance");
  AvoidSequenceScore score;
  score.name = seq.Info().name.empty() ? path.filename().string() : seq.Info().name;
  score.pairs = seq.Size() > 0 ? seq.Size() - 1 : 0;
  // The true map has no features: its free sectors are the ones in view without true contacts.
  obstacles::PolarMapOptions truth_polar = options.avoid.polar;
  truth_polar.free_needs_ground = false;
  obstacles::PolarMapper truth_mapper(seq.Camera(), truth_polar);
  std::vector<obstacles::Gap> truth_gaps;
  const double roi = options.avoid.polar.roi_radius_m;
  RunAvoidOnSequence(
      seq, options,
      [&](std::size_t i, const cv::Mat&, const obstacles::PairResult&, const obstacles::AvoidResult& r) {
        ++score.pairs_ok;
        const std::vector<ContactPoint> truth = LabelContacts(seq.Camera(), seq.LoadLabel(i));
        const obstacles::PolarMap& tm = truth_mapper.Build(truth);
        AvoidFrameScore f;
        f.frame = i;
        for (std::size_t k = 0; k < tm.sectors.size(); ++k) {
          const auto& ts = tm.sectors[k];
          const auto& ds = r.map->sectors[k];
          if (!ts.in_view) continue;
          const bool t = ts.state == SectorState::kOccupied, d = ds.state == SectorState::kOccupied;
          ++f.sectors_in_view;
          f.sectors_agree += t == d;
          f.true_occupied += t;
          f.detected_occupied += d;
          f.both_occupied += t && d;
        }
        obstacles::FindGaps(tm, options.avoid.gap, &truth_gaps);
        f.true_stop = obstacles::ChooseSteering(truth_gaps).stop;
        f.stop = r.decision.stop;
        f.steer_deg = r.decision.steer_deg;
        if (f.steer_deg) {
          bool free = true;
          for (const ContactPoint& c : truth)
            if (c.range_m <= roi && std::abs(c.bearing_deg - *f.steer_deg) <= eval_options.free_cone_deg) free = false;
          f.steer_truly_free = free;
        }
        score.frames.push_back(f);
        if (progress) progress(i, score.pairs);
      },
      [&](std::size_t i, const obstacles::PairResult& pair) {
        ++score.skipped[obstacles::PairStatusName(pair.status)];
        if (progress) progress(i, score.pairs);
      });
  return score;
}

AvoidTotals Totals(const std::vector<AvoidFrameScore>& frames) {
  AvoidTotals t;
  for (const AvoidFrameScore& f : frames) {
    ++t.frames;
    t.sectors_in_view += f.sectors_in_view;
    t.sectors_agree += f.sectors_agree;
    t.true_occupied += f.true_occupied;
    t.detected_occupied += f.detected_occupied;
    t.both_occupied += f.both_occupied;
    t.stops += f.stop;
    t.true_stops += f.true_stop;
    if (f.steer_truly_free) {
      ++t.moving;
      t.moving_free += *f.steer_truly_free;
    }
  }
  return t;
}

}  // namespace squint::eval
