// The three distance-to-end cues of paper §4.2: time to contact (eq. 3), Jeffrey divergence
// (eq. 4) and entropy change (§4.2.3).
#include "squint/corridor/distance_measures.hpp"

#include <cmath>
#include <span>

#include "squint/corridor/information.hpp"

namespace squint::corridor {
namespace {

constexpr int kW = kGlanceWidth;
constexpr int kH = kGlanceHeight;

void SetNoEstimate(DistanceMeasureResult& out, Reason reason) {
  out.dist_m.reset();
  out.reason = reason;
}

// Range check shared by the cues.
void SetDistance(const DistanceOptions& options, double dist_m, DistanceMeasureResult& out) {
  if (!std::isfinite(dist_m) || dist_m < options.min_m || dist_m > options.max_m) {
    return SetNoEstimate(out, Reason::kOutOfRange);
  }
  out.dist_m = dist_m;
  out.reason = Reason::kNone;
}

}  // namespace

namespace {

// Σ G² and Σ G·I_t of eq. 3 over the interior pixels. I_x, I_y: central differences averaged over
// both frames; I_t = I2 − I1; G = x·I_x + y·I_y about (cx, cy).
struct TtcSums {
  double gg = 0.0;
  double git = 0.0;
};

TtcSums SumTtc(const Glance& a, const Glance& b, double cx, double cy) {
  // Single precision inside a row (vectorisable), double across rows.
  TtcSums s;
  for (int v = 1; v < kH - 1; ++v) {
    const float y = static_cast<float>(v - cy);
    const std::uint8_t* a0 = a.pixels.data() + v * kW;
    const std::uint8_t* b0 = b.pixels.data() + v * kW;
    float gg = 0.0f, git = 0.0f;
    for (int u = 1; u < kW - 1; ++u) {
      const float x = static_cast<float>(u - cx);
      const int ix = (a0[u + 1] - a0[u - 1]) + (b0[u + 1] - b0[u - 1]);
      const int iy = (a0[u + kW] - a0[u - kW]) + (b0[u + kW] - b0[u - kW]);
      const float g = 0.25f * (x * static_cast<float>(ix) + y * static_cast<float>(iy));  // ix, iy: 4 × mean derivative
      gg += g * g;
      git += g * static_cast<float>(b0[u] - a0[u]);
    }
    s.gg += gg;
    s.git += git;
  }
  return s;
}

}  // namespace

std::optional<double> TimeToContactFrames(const Glance& previous, const Glance& current, double cx, double cy) {
  const TtcSums s = SumTtc(previous, current, cx, cy);
  if (s.gg == 0.0 || s.git == 0.0) return std::nullopt;
  return -s.gg / s.git;
}

void TimeToContactDistance::Measure(const PreparedGlance& previous, const PreparedGlance& current,
                                    std::optional<double> travelled_m, DistanceMeasureResult& out) const {
  out.cue = Cue();
  out.raw.reset();
  if (previous.glance.pixels == current.glance.pixels) return SetNoEstimate(out, Reason::kIdenticalFrames);
  if (previous.Uniform() && current.Uniform()) return SetNoEstimate(out, Reason::kUniformFrame);
  const TtcSums s = SumTtc(previous.glance, current.glance, cx_, cy_);
  if (s.gg == 0.0) return SetNoEstimate(out, Reason::kZeroGradient);
  if (s.git == 0.0) return SetNoEstimate(out, Reason::kTtcDenominatorZero);
  const double tau_frames = -s.gg / s.git;
  out.raw = tau_frames;
  if (tau_frames <= 0.0) return SetNoEstimate(out, Reason::kNotApproaching);
  if (!travelled_m || !(*travelled_m > 0.0)) return SetNoEstimate(out, Reason::kNoTravel);
  SetDistance(options_, options_.ttc_scale * tau_frames * *travelled_m + options_.ttc_bias_m, out);
}

void JeffreyDistance::Measure(const PreparedGlance& previous, const PreparedGlance& current,
                              std::optional<double> /*travelled_m*/, DistanceMeasureResult& out) const {
  out.cue = Cue();
  out.raw.reset();
  if (previous.glance.pixels == current.glance.pixels) return SetNoEstimate(out, Reason::kIdenticalFrames);
  const std::span<const std::uint32_t> p(previous.histogram.data(), static_cast<std::size_t>(previous.image_bins));
  const std::span<const std::uint32_t> q(current.histogram.data(), static_cast<std::size_t>(current.image_bins));
  const double j = JeffreyDivergence(p, q);
  out.raw = j;
  SetDistance(options_, options_.beta2 - options_.alpha2 * j, out);
}

void EntropyDistance::Measure(const PreparedGlance& previous, const PreparedGlance& current,
                              std::optional<double> /*travelled_m*/, DistanceMeasureResult& out) const {
  out.cue = Cue();
  out.raw.reset();
  if (previous.glance.pixels == current.glance.pixels) return SetNoEstimate(out, Reason::kIdenticalFrames);
  // The paper's sign (H1 − H2) depends on whether entropy falls or rises towards the end; the
  // magnitude of the change is what scales inversely with distance, so |ΔH| is used.
  const double dh = previous.entropy - current.entropy;
  out.raw = dh;
  if (dh == 0.0) return SetNoEstimate(out, Reason::kIdenticalFrames);
  SetDistance(options_, options_.alpha3 / std::abs(dh), out);
}

}  // namespace squint::corridor
