// The three distance-to-end cues of paper §4.2: time to contact (eq. 3), Jeffrey divergence
// (eq. 4) and entropy change (§4.2.3).
#include "squint/corridor/distance_measures.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "squint/core/error.hpp"
#include "squint/corridor/information.hpp"

namespace squint::corridor {
namespace {

constexpr int kW = kGlanceWidth;
constexpr int kH = kGlanceHeight;

void SetNoEstimate(DistanceMeasureResult& out, Reason reason) {
  out.instant_m.reset();
  out.dist_m.reset();
  out.reason = reason;
}

// Range check shared by the cues: the global range and the cue's validity window.
std::optional<double> InRange(const DistanceOptions& options, DistanceCue cue, double dist_m) {
  const int c = static_cast<int>(cue);
  if (!std::isfinite(dist_m) || dist_m < options.min_m || dist_m > options.max_m) return std::nullopt;
  if (dist_m < options.valid_min_m[c] || dist_m > options.valid_max_m[c]) return std::nullopt;
  return dist_m;
}

// Sets out.model_input and the estimate from it (out.instant_m and out.dist_m alike).
void SetInput(const DistanceMeasure& measure, double input, DistanceMeasureResult& out) {
  out.model_input = input;
  out.instant_m = measure.Distance(input);
  out.dist_m = out.instant_m;
  out.reason = out.dist_m ? Reason::kNone : Reason::kOutOfRange;
}

void Clear(DistanceMeasureResult& out, DistanceCue cue) {
  out.cue = cue;
  out.raw.reset();
  out.model_input.reset();
  out.filtered_input.reset();
  out.instant_m.reset();
  out.dist_m.reset();
  out.baseline_frames = 0;
  out.fused = false;
}

}  // namespace

namespace {

// The sums of eq. 3 over the interior pixels. I_x, I_y: central differences averaged over both
// frames; I_t = I2 − I1; G = x·I_x + y·I_y about (cx, cy). With gain compensation also the
// sums for regressing I_t on G, the mean brightness M = (I1 + I2)/2 and 1 jointly, so that a
// change of camera gain or offset between the frames (I_t ∝ M) does not pass for expansion.
struct TtcSums {
  double gg = 0.0;
  double git = 0.0;
  // Gain-compensated: Σ G·M, Σ G, Σ M², Σ M, n, Σ M·I_t, Σ I_t.
  double gm = 0.0, g1 = 0.0, mm = 0.0, m1 = 0.0, n = 0.0, mit = 0.0, it1 = 0.0;

  // The coefficient c of I_t ≈ c·G (+ e·M + f); τ = −1/c. None when singular.
  std::optional<double> Slope(bool gain) const {
    if (gg == 0.0) return std::nullopt;
    if (!gain) return git / gg;
    Eigen::Matrix3d a;
    a << gg, gm, g1, gm, mm, m1, g1, m1, n;
    const Eigen::Vector3d b(git, mit, it1);
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(a);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return std::nullopt;
    const Eigen::Vector3d x = ldlt.solve(b);
    // A rank-deficient system (e.g. G ∝ M) leaves the slope undetermined.
    if (!x.allFinite() || (a * x - b).norm() > 1e-6 * (b.norm() + 1.0)) return std::nullopt;
    return x(0);
  }
};

template <bool kGain>
TtcSums SumTtcImpl(const Glance& a, const Glance& b, double cx, double cy) {
  // Single precision inside a row (vectorisable), double across rows.
  TtcSums s;
  for (int v = 1; v < kH - 1; ++v) {
    const float y = static_cast<float>(v - cy);
    const std::uint8_t* a0 = a.pixels.data() + v * kW;
    const std::uint8_t* b0 = b.pixels.data() + v * kW;
    float gg = 0.0f, git = 0.0f, gm = 0.0f, g1 = 0.0f, mm = 0.0f, m1 = 0.0f, mit = 0.0f, it1 = 0.0f;
    for (int u = 1; u < kW - 1; ++u) {
      const float x = static_cast<float>(u - cx);
      const int ix = (a0[u + 1] - a0[u - 1]) + (b0[u + 1] - b0[u - 1]);
      const int iy = (a0[u + kW] - a0[u - kW]) + (b0[u + kW] - b0[u - kW]);
      const float g = 0.25f * (x * static_cast<float>(ix) + y * static_cast<float>(iy));  // ix, iy: 4 × mean derivative
      const float it = static_cast<float>(b0[u] - a0[u]);
      gg += g * g;
      git += g * it;
      if constexpr (kGain) {
        const float m = 0.5f * static_cast<float>(a0[u] + b0[u]);
        gm += g * m;
        g1 += g;
        mm += m * m;
        m1 += m;
        mit += m * it;
        it1 += it;
      }
    }
    s.gg += gg;
    s.git += git;
    s.gm += gm;
    s.g1 += g1;
    s.mm += mm;
    s.m1 += m1;
    s.mit += mit;
    s.it1 += it1;
  }
  s.n = static_cast<double>((kW - 2) * (kH - 2));
  return s;
}

// The plain sums (two accumulators per pixel) unless gain compensation needs the other six.
TtcSums SumTtc(const Glance& a, const Glance& b, double cx, double cy, bool gain) {
  return gain ? SumTtcImpl<true>(a, b, cx, cy) : SumTtcImpl<false>(a, b, cx, cy);
}

}  // namespace

std::optional<double> TimeToContactFrames(const Glance& previous, const Glance& current, double cx, double cy,
                                          bool gain_compensation) {
  const std::optional<double> c = SumTtc(previous, current, cx, cy, gain_compensation).Slope(gain_compensation);
  if (!c || *c == 0.0) return std::nullopt;
  return -1.0 / *c;
}

void TimeToContactDistance::Measure(const PreparedGlance& previous, const PreparedGlance& current,
                                    std::optional<double> travelled_m, DistanceMeasureResult& out) const {
  if (previous.glance.pixels != current.glance.pixels && previous.Uniform() && current.Uniform()) {
    Clear(out, Cue());
    return SetNoEstimate(out, Reason::kUniformFrame);
  }
  MeasureBaseline(previous.glance, current.glance, 1, travelled_m, out);
}

void TimeToContactDistance::MeasureBaseline(const Glance& earlier, const Glance& current, int baseline_frames,
                                            std::optional<double> travelled_m, DistanceMeasureResult& out) const {
  Clear(out, Cue());
  out.baseline_frames = baseline_frames;
  if (earlier.pixels == current.pixels) return SetNoEstimate(out, Reason::kIdenticalFrames);
  const TtcSums s = SumTtc(earlier, current, cx_, cy_, options_.ttc_gain_compensation);
  if (s.gg == 0.0) return SetNoEstimate(out, Reason::kZeroGradient);
  const std::optional<double> c = s.Slope(options_.ttc_gain_compensation);
  if (!c || *c == 0.0) return SetNoEstimate(out, Reason::kTtcDenominatorZero);
  const double tau_frames = -1.0 / *c;
  out.raw = tau_frames;
  if (tau_frames <= 0.0) return SetNoEstimate(out, Reason::kNotApproaching);
  if (!travelled_m || !(*travelled_m > 0.0)) return SetNoEstimate(out, Reason::kNoTravel);
  SetInput(*this, tau_frames * *travelled_m - 0.5 * *travelled_m, out);
}

namespace {

// Sums for the NCC of one candidate scale: Σx, Σx², Σxy over the window, x the magnified
// earlier glance (bilinear), y the current one.
struct NccSums {
  float sx = 0.0f, sxx = 0.0f, sxy = 0.0f;
};

// The window of the current glance (every `step`-th row and column from (u0, v0)) and its own
// sums, shared by every candidate scale.
struct ScaleWindow {
  int u0, u1, v0, v1, step;
  double n, sy, syy;
};

ScaleWindow MakeWindow(const TtcImage& current, int u0, int u1, int v0, int v1, int step) {
  ScaleWindow w{u0, u1, v0, v1, step, 0.0, 0.0, 0.0};
  for (int v = v0; v <= v1; v += step)
    for (int u = u0; u <= u1; u += step) {
      const double y = current.At(u, v);
      w.n += 1.0;
      w.sy += y;
      w.syy += y * y;
    }
  return w;
}

NccSums SumScale(const TtcImage& earlier, const TtcImage& current, const ScaleWindow& w, double cx, double cy,
                 double scale) {
  const float inv = static_cast<float>(1.0 / scale);
  const float fcx = static_cast<float>(cx), fcy = static_cast<float>(cy);
  const int iw = current.width, ih = current.height;
  // Sources lie between the centre and p, so inside the glance; clamped for the bilinear cell.
  // The column lookup depends on the scale only: one table per call (entries u0..u1 only).
  std::array<int, kMaxTtcWidth> col;
  std::array<float, kMaxTtcWidth> frac;
  for (int u = w.u0; u <= w.u1; u += w.step) {
    const float sx = std::clamp(fcx + (static_cast<float>(u) - fcx) * inv, 0.0f, iw - 1.001f);
    col[u] = static_cast<int>(sx);
    frac[u] = sx - static_cast<float>(col[u]);
  }
  NccSums s;
  for (int v = w.v0; v <= w.v1; v += w.step) {
    const float sy = std::clamp(fcy + (static_cast<float>(v) - fcy) * inv, 0.0f, ih - 1.001f);
    const int y0 = static_cast<int>(sy);
    const float fy = sy - static_cast<float>(y0);
    const std::uint8_t* r0 = earlier.data + y0 * iw;
    const std::uint8_t* r1 = r0 + iw;
    const std::uint8_t* cur = current.data + v * iw;
    for (int u = w.u0; u <= w.u1; u += w.step) {
      const int x0 = col[u];
      const float fx = frac[u];
      const float top = r0[x0] + fx * static_cast<float>(r0[x0 + 1] - r0[x0]);
      const float bottom = r1[x0] + fx * static_cast<float>(r1[x0 + 1] - r1[x0]);
      const float x = top + fy * (bottom - top);
      s.sx += x;
      s.sxx += x * x;
      s.sxy += x * static_cast<float>(cur[u]);
    }
  }
  return s;
}

double Ncc(const NccSums& s, const ScaleWindow& w) {
  const double cxx = s.sxx - static_cast<double>(s.sx) * s.sx / w.n;
  const double cxy = s.sxy - static_cast<double>(s.sx) * w.sy / w.n;
  const double cyy = w.syy - w.sy * w.sy / w.n;
  if (!(cxx > 0.0) || !(cyy > 0.0)) return -2.0;
  return cxy / std::sqrt(cxx * cyy);
}

// Gauss–Newton sums at one scale: besides the NCC's Σx, Σx², Σxy also g = ∂x/∂σ, the exact
// derivative of the bilinear interpolant (from the same four corners), and Σg, Σg², Σxg, Σgy.
struct GnSums {
  double sx = 0.0, sxx = 0.0, sxy = 0.0, sg = 0.0, sgg = 0.0, sxg = 0.0, sgy = 0.0;
};

GnSums SumScaleGn(const TtcImage& earlier, const TtcImage& current, const ScaleWindow& w, double cx, double cy,
                  double scale) {
  const float inv = static_cast<float>(1.0 / scale);
  const float dinv = static_cast<float>(-1.0 / (scale * scale));  // d(1/σ)/dσ
  const float fcx = static_cast<float>(cx), fcy = static_cast<float>(cy);
  const int iw = current.width, ih = current.height;
  std::array<int, kMaxTtcWidth> col;
  std::array<float, kMaxTtcWidth> frac;
  std::array<float, kMaxTtcWidth> dcol;  // ∂(source column)/∂σ; 0 where clamped
  for (int u = w.u0; u <= w.u1; u += w.step) {
    const float raw = fcx + (static_cast<float>(u) - fcx) * inv;
    const float sx = std::clamp(raw, 0.0f, iw - 1.001f);
    col[u] = static_cast<int>(sx);
    frac[u] = sx - static_cast<float>(col[u]);
    dcol[u] = sx == raw ? (static_cast<float>(u) - fcx) * dinv : 0.0f;
  }
  GnSums s;
  for (int v = w.v0; v <= w.v1; v += w.step) {
    const float raw = fcy + (static_cast<float>(v) - fcy) * inv;
    const float sy = std::clamp(raw, 0.0f, ih - 1.001f);
    const float drow = sy == raw ? (static_cast<float>(v) - fcy) * dinv : 0.0f;
    const int y0 = static_cast<int>(sy);
    const float fy = sy - static_cast<float>(y0);
    const std::uint8_t* r0 = earlier.data + y0 * iw;
    const std::uint8_t* r1 = r0 + iw;
    const std::uint8_t* cur = current.data + v * iw;
    float sx_ = 0.0f, sxx = 0.0f, sxy = 0.0f, sg = 0.0f, sgg = 0.0f, sxg = 0.0f, sgy = 0.0f;
    for (int u = w.u0; u <= w.u1; u += w.step) {
      const int x0 = col[u];
      const float fx = frac[u];
      const float a = r0[x0], b = r0[x0 + 1], c = r1[x0], d = r1[x0 + 1];
      const float top = a + fx * (b - a);
      const float bottom = c + fx * (d - c);
      const float x = top + fy * (bottom - top);
      const float gx = (b - a) + fy * ((d - c) - (b - a));  // ∂x/∂(source column)
      const float g = gx * dcol[u] + (bottom - top) * drow;
      const float y = static_cast<float>(cur[u]);
      sx_ += x;
      sxx += x * x;
      sxy += x * y;
      sg += g;
      sgg += g * g;
      sxg += x * g;
      sgy += g * y;
    }
    s.sx += sx_;
    s.sxx += sxx;
    s.sxy += sxy;
    s.sg += sg;
    s.sgg += sgg;
    s.sxg += sxg;
    s.sgy += sgy;
  }
  return s;
}

// Gauss–Newton on σ with the NCC's gain and offset free: at each iterate the current glance y is
// regressed on [x(σ), ∂x/∂σ, 1] (x the magnified earlier glance), y ≈ a·x + c·∂x/∂σ + b, i.e. the
// first-order model y ≈ a·x(σ + c/a) + b; the step is c/a (at most ±kMaxStep). Each iterate's
// NCC comes with its sums; a step that lowers it is halved. Returns the best iterate (σ, NCC);
// the NCC is −2 when a side is uniform.
struct GnResult {
  double scale = 1.0;
  double ncc = -2.0;
  // Standard error of the scale at the best iterate (the linearised regression's; infinite when
  // the window carries no scale information).
  double se = HUGE_VAL;
};

GnResult RefineScale(const TtcImage& earlier, const TtcImage& current, const ScaleWindow& w, double cx, double cy,
                     double start, double max_scale) {
  constexpr int kMaxIterations = 5;
  constexpr double kMaxStep = 0.05, kTolerance = 2e-4;
  const double cyy = w.syy - w.sy * w.sy / w.n;
  GnResult best;
  double scale = std::clamp(start, 1.0, max_scale);
  for (int it = 0; it < kMaxIterations; ++it) {
    const GnSums s = SumScaleGn(earlier, current, w, cx, cy, scale);
    const double cxx = s.sxx - s.sx * s.sx / w.n;
    const double cxy = s.sxy - s.sx * w.sy / w.n;
    if (!(cxx > 0.0) || !(cyy > 0.0)) return best;
    const double ncc = cxy / std::sqrt(cxx * cyy);
    if (ncc <= best.ncc) {  // worse than the best iterate: back half-way towards it
      const double back = 0.5 * (scale + best.scale);
      if (std::abs(back - best.scale) < kTolerance) break;
      scale = back;
      continue;
    }
    best = {scale, ncc, HUGE_VAL};
    const double cgg = s.sgg - s.sg * s.sg / w.n;
    const double cxg = s.sxg - s.sx * s.sg / w.n;
    const double cgy = s.sgy - s.sg * w.sy / w.n;
    const double det = cxx * cgg - cxg * cxg;
    if (!(det > 1e-12 * cxx * cgg)) break;  // no scale information (e.g. no gradient)
    const double a = (cgg * cxy - cxg * cgy) / det;
    const double c = (cxx * cgy - cxg * cxy) / det;
    if (!(a > 0.0)) break;  // anti-correlated: no meaningful step
    // se(σ) = se(c) / a, se(c)² = residual variance · cxx / det.
    if (w.n > 3.0) {
      const double rss = std::max(0.0, cyy - a * cxy - c * cgy);
      best.se = std::sqrt(rss / (w.n - 3.0) * cxx / det) / a;
    }
    const double next = std::clamp(scale + std::clamp(c / a, -kMaxStep, kMaxStep), 1.0, max_scale);
    if (std::abs(next - scale) < kTolerance) {
      // Converged: the last step is below the tolerance; its end is the answer.
      best.scale = next;
      break;
    }
    scale = next;
  }
  return best;
}

// The glance columns u0..u1 and rows v0..v1 within ±half sizes of (cx, cy); none when empty.
struct PixelBox {
  int u0, u1, v0, v1;
};
std::optional<PixelBox> WindowBox(int iw, int ih, double cx, double cy, double half_width_px,
                                  double half_height_px) {
  const PixelBox b{std::max(0, static_cast<int>(std::ceil(cx - half_width_px))),
                   std::min(iw - 1, static_cast<int>(std::floor(cx + half_width_px))),
                   std::max(0, static_cast<int>(std::ceil(cy - half_height_px))),
                   std::min(ih - 1, static_cast<int>(std::floor(cy + half_height_px)))};
  if (b.u1 < b.u0 || b.v1 < b.v0) return std::nullopt;
  return b;
}

// Grey-level standard deviation of the current glance over a window.
double WindowContrast(const ScaleWindow& w) {
  return std::sqrt(std::max(0.0, w.syy / w.n - (w.sy / w.n) * (w.sy / w.n)));
}

}  // namespace

std::optional<ScaleMatch> ExpansionScale(const TtcImage& earlier, const TtcImage& current, double cx, double cy,
                                         double half_width_px, double half_height_px, double max_scale,
                                         std::optional<double> initial_scale, double accept_ncc) {
  if (!std::isfinite(cx) || !std::isfinite(cy) || !(max_scale > 1.0)) return std::nullopt;
  const std::optional<PixelBox> box =
      WindowBox(current.width, current.height, cx, cy, half_width_px, half_height_px);
  if (!box) return std::nullopt;
  const auto [u0, u1, v0, v1] = *box;
  const ScaleWindow full = MakeWindow(current, u0, u1, v0, v1, 1);
  if (full.n < 12.0) return std::nullopt;
  const double contrast = WindowContrast(full);
  // Predicted scale: Gauss–Newton from it, accepted when its NCC reaches accept_ncc.
  if (initial_scale && std::isfinite(*initial_scale)) {
    const GnResult r = RefineScale(earlier, current, full, cx, cy, *initial_scale, max_scale);
    if (r.ncc <= -2.0) return std::nullopt;  // a uniform side
    if (r.ncc >= accept_ncc) return ScaleMatch{r.scale, r.ncc, contrast, false};
  }
  // Grid: every 0.01 on every other row and column of a large window (a quarter of the work),
  // then Gauss–Newton on every pixel from the grid's best.
  const ScaleWindow coarse_window = full.n > 256.0 ? MakeWindow(current, u0, u1, v0, v1, 2) : full;
  constexpr double kCoarse = 0.01;
  const int n_coarse = static_cast<int>(std::ceil((max_scale - 1.0) / kCoarse - 1e-9));
  double centre = 1.0, best = Ncc(SumScale(earlier, current, coarse_window, cx, cy, 1.0), coarse_window);
  for (int i = 1; i <= n_coarse; ++i) {
    const double sc = std::min(max_scale, 1.0 + i * kCoarse);
    const double r = Ncc(SumScale(earlier, current, coarse_window, cx, cy, sc), coarse_window);
    if (r > best) best = r, centre = sc;
  }
  if (best <= -2.0) return std::nullopt;  // a uniform side
  const GnResult r = RefineScale(earlier, current, full, cx, cy, centre, max_scale);
  if (r.ncc <= -2.0) return std::nullopt;
  return ScaleMatch{r.scale, r.ncc, contrast, true};
}

std::optional<CellScales> CellExpansionScales(const TtcImage& earlier, const TtcImage& current, double cx,
                                              double cy, double half_width_px, double half_height_px,
                                              double max_scale, double start_scale, double cell_px,
                                              double min_contrast, double min_ncc, double max_se,
                                              int max_cells) {
  if (!std::isfinite(cx) || !std::isfinite(cy) || !(max_scale > 1.0) || !(cell_px >= 1.0)) return std::nullopt;
  const std::optional<PixelBox> box =
      WindowBox(current.width, current.height, cx, cy, half_width_px, half_height_px);
  if (!box) return std::nullopt;
  const auto [u0, u1, v0, v1] = *box;
  // Cells of about cell_px × cell_px: as many as fit (at least one per direction), the window's
  // columns and rows shared out evenly.
  const int nu = std::max(1, static_cast<int>(std::lround((u1 - u0 + 1) / cell_px)));
  const int nv = std::max(1, static_cast<int>(std::lround((v1 - v0 + 1) / cell_px)));
  // Visited nearest the expansion centre first (ties: row-major order), so that with max_cells
  // only the cells that will count are refined.
  struct Cell {
    int u0, u1, v0, v1;
    double radius;
  };
  std::array<Cell, kMaxTtcCells> grid{};
  int n_grid = 0;
  for (int j = 0; j < nv && n_grid < kMaxTtcCells; ++j)
    for (int i = 0; i < nu && n_grid < kMaxTtcCells; ++i) {
      Cell& c = grid[n_grid++];
      c.u0 = u0 + (u1 - u0 + 1) * i / nu;
      c.u1 = u0 + (u1 - u0 + 1) * (i + 1) / nu - 1;
      c.v0 = v0 + (v1 - v0 + 1) * j / nv;
      c.v1 = v0 + (v1 - v0 + 1) * (j + 1) / nv - 1;
      c.radius = std::hypot(0.5 * (c.u0 + c.u1) - cx, 0.5 * (c.v0 + c.v1) - cy);
    }
  for (int k = 1; k < n_grid; ++k)  // insertion sort: stable, in place, no allocation
    for (int m = k; m > 0 && grid[m].radius < grid[m - 1].radius; --m) std::swap(grid[m], grid[m - 1]);
  CellScales out;
  for (int k = 0; k < n_grid; ++k) {
    if (max_cells > 0 && out.count >= max_cells) break;
    const Cell& c = grid[k];
    const ScaleWindow w = MakeWindow(current, c.u0, c.u1, c.v0, c.v1, 1);
    if (w.n < 6.0) continue;
    if (WindowContrast(w) < min_contrast) continue;
    const GnResult r = RefineScale(earlier, current, w, cx, cy, start_scale, max_scale);
    if (r.ncc < min_ncc || !(r.se <= max_se)) continue;
    out.radius_px[out.count] = c.radius;
    out.scale[out.count++] = r.scale;
  }
  return out;
}

double LowerQuantile(std::span<double> values, double q) {
  if (values.empty()) return 0.0;
  const std::size_t k = static_cast<std::size_t>(std::floor(std::clamp(q, 0.0, 1.0) * (values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

void TimeToContactDistance::MeasureScale(const TtcImage& earlier, const TtcImage& current, int baseline_frames,
                                         std::optional<double> travelled_m, std::optional<double> reference_m,
                                         DistanceMeasureResult& out) const {
  Clear(out, Cue());
  out.baseline_frames = baseline_frames;
  if (earlier.width != current.width || earlier.height != current.height)
    return SetNoEstimate(out, Reason::kNoPreviousFrame);
  const std::size_t n_px = static_cast<std::size_t>(current.width) * static_cast<std::size_t>(current.height);
  if (std::equal(earlier.data, earlier.data + n_px, current.data)) return SetNoEstimate(out, Reason::kIdenticalFrames);
  // The geometry in this image's pixels: the glance's (cx_, cy_, focal_px_ and the options'
  // sizes in glance pixels) scaled by the image's size over the glance's (fx = fy = 1 for a
  // 32×24 image: the products are exact; the centre keeps cx_, cy_ themselves).
  const bool glance_size = current.width == kW && current.height == kH;
  const double fx = static_cast<double>(current.width) / kW;
  const double fy = static_cast<double>(current.height) / kH;
  const double cx = glance_size ? cx_ : (cx_ + 0.5) * fx - 0.5;
  const double cy = glance_size ? cy_ : (cy_ + 0.5) * fy - 0.5;
  const double focal = focal_px_ * fx;
  const double img_w = current.width, img_h = current.height;
  const double min_w = std::min(options_.ttc_window_min_px * fx, img_w);
  const double min_h = std::min(options_.ttc_window_min_height_px * fy, img_h);
  double half_w = options_.ttc_whole_glance_first ? img_w : min_w;
  double half_h = options_.ttc_whole_glance_first ? img_h : min_h;
  if (reference_m && *reference_m > 0.0 && focal > 0.0) {
    half_w = std::clamp(options_.ttc_window_half_width_m * focal / *reference_m, min_w, img_w);
    if (camera_height_m_ > 0.0)
      half_h = std::clamp(options_.ttc_window_height_factor * camera_height_m_ * focal / *reference_m, min_h,
                          img_h);
    else
      half_h = std::clamp(0.75 * half_w, min_h, img_h);
  }
  // Predicted magnification: a plane at the reference distance d̂ (now) seen s metres earlier
  // magnifies by (d̂ + s) / d̂.
  std::optional<double> predicted;
  if (reference_m && *reference_m > 0.0 && travelled_m && *travelled_m > 0.0)
    predicted = 1.0 + *travelled_m / *reference_m;
  const std::optional<ScaleMatch> m = ExpansionScale(earlier, current, cx, cy, half_w, half_h,
                                                     options_.ttc_max_scale, predicted, options_.ttc_min_ncc);
  if (!m || m->contrast < options_.ttc_min_contrast || m->ncc < options_.ttc_min_ncc)
    return SetNoEstimate(out, Reason::kZeroGradient);
  double scale = m->scale;
  if (options_.ttc_cell_px > 0.0 && m->scale - 1.0 >= options_.ttc_cell_min_expansion) {
    // Far-structure cells: the window's magnification is refined per cell, and a low quantile
    // of the cells' magnifications (the farthest structure) replaces it.
    // Cells whose scale is less certain than a fraction of the expected expansion (predicted,
    // else the window's) carry no evidence of their own.
    const double expected = std::max(predicted ? *predicted - 1.0 : m->scale - 1.0, 1e-3);
    // Only the ttc_cell_nearest cells nearest the expansion centre (where the end of the
    // corridor is); with ttc_cell_nearest_at_min_window only while the window is at its minimum
    // size (far away, where it holds more than the end wall).
    const bool at_min = half_w <= min_w + 1e-9 && half_h <= min_h + 1e-9;
    const int max_cells =
        options_.ttc_cell_nearest > 0 && (!options_.ttc_cell_nearest_at_min_window || at_min)
            ? options_.ttc_cell_nearest
            : 0;
    // The cell size in this image's pixels (ttc_cell_px is in glance pixels).
    const double cell_px = options_.ttc_cell_px * std::sqrt(fx * fy);
    std::optional<CellScales> cells = CellExpansionScales(
        earlier, current, cx, cy, half_w, half_h, options_.ttc_max_scale, m->scale, cell_px,
        options_.ttc_min_contrast, options_.ttc_min_ncc, options_.ttc_cell_max_se_fraction * expected, max_cells);
    if (cells && cells->count >= options_.ttc_cell_min_count)
      scale = LowerQuantile(std::span<double>(cells->scale.data(), static_cast<std::size_t>(cells->count)),
                            options_.ttc_cell_quantile);
  }
  out.raw = scale - 1.0;
  if (!(scale > 1.0)) return SetNoEstimate(out, Reason::kNotApproaching);
  if (scale >= options_.ttc_max_scale) return SetNoEstimate(out, Reason::kOutOfRange);
  if (!travelled_m || !(*travelled_m > 0.0)) return SetNoEstimate(out, Reason::kNoTravel);
  SetInput(*this, *travelled_m / (scale - 1.0), out);
}

void SmoothGlance(const Glance& in, Glance& out) {
  SmoothTtcImage(TtcView(in), out.pixels.data());
}

void SmoothTtcImage(const TtcImage& in, std::uint8_t* out) {
  // Separable [1 2 1] / 4 in each direction; the border pixel is repeated.
  const int w = in.width, h = in.height;
  std::array<std::uint16_t, kMaxTtcPixels> rows;
  for (int v = 0; v < h; ++v) {
    const std::uint8_t* p = in.data + v * w;
    std::uint16_t* r = rows.data() + v * w;
    for (int u = 0; u < w; ++u) r[u] = p[std::max(u - 1, 0)] + 2 * p[u] + p[std::min(u + 1, w - 1)];
  }
  for (int v = 0; v < h; ++v) {
    const std::uint16_t* a = rows.data() + std::max(v - 1, 0) * w;
    const std::uint16_t* b = rows.data() + v * w;
    const std::uint16_t* c = rows.data() + std::min(v + 1, h - 1) * w;
    std::uint8_t* o = out + v * w;
    for (int u = 0; u < w; ++u) o[u] = static_cast<std::uint8_t>((a[u] + 2 * b[u] + c[u] + 8) / 16);
  }
}

void MakeAreaImage(const PixelView& frame, int width, int height, std::uint8_t* out) {
  SQUINT_ENSURE(!frame.Empty(), "MakeAreaImage needs a non-empty frame");
  SQUINT_ENSURE(frame.channels == 1 || frame.channels == 3 || frame.channels == 4,
                "MakeAreaImage needs 1, 3 or 4 channels");
  SQUINT_ENSURE(width >= 1 && height >= 1 && width <= frame.width && height <= frame.height &&
                    width * height <= kMaxTtcPixels,
                "MakeAreaImage needs a size within the frame's and kMaxTtcPixels");
  const double sx = static_cast<double>(frame.width) / width, sy = static_cast<double>(frame.height) / height;
  for (int v = 0; v < height; ++v) {
    const double y0 = v * sy, y1 = (v + 1) * sy;
    const int r0 = static_cast<int>(std::floor(y0)), r1 = std::min(frame.height, static_cast<int>(std::ceil(y1)));
    for (int u = 0; u < width; ++u) {
      const double x0 = u * sx, x1 = (u + 1) * sx;
      const int c0 = static_cast<int>(std::floor(x0)), c1 = std::min(frame.width, static_cast<int>(std::ceil(x1)));
      double sum = 0.0;
      for (int r = r0; r < r1; ++r) {
        const double wy = std::min<double>(r + 1, y1) - std::max<double>(r, y0);
        const std::uint8_t* row = frame.data + r * frame.stride;
        double line = 0.0;
        for (int c = c0; c < c1; ++c)
          line += (std::min<double>(c + 1, x1) - std::max<double>(c, x0)) * GreyAt(row, c, frame.channels);
        sum += wy * line;
      }
      out[v * width + u] = static_cast<std::uint8_t>(std::clamp(std::floor(sum / (sx * sy) + 0.5), 0.0, 255.0));
    }
  }
}

std::optional<double> TimeToContactDistance::Distance(double model_input) const {
  return InRange(options_, Cue(), options_.ttc_scale * model_input + options_.ttc_bias_m);
}

void JeffreyDistance::Measure(const PreparedGlance& previous, const PreparedGlance& current,
                              std::optional<double> /*travelled_m*/, DistanceMeasureResult& out) const {
  Clear(out, Cue());
  if (previous.glance.pixels == current.glance.pixels) return SetNoEstimate(out, Reason::kIdenticalFrames);
  const std::span<const std::uint32_t> p(previous.histogram.data(), static_cast<std::size_t>(previous.image_bins));
  const std::span<const std::uint32_t> q(current.histogram.data(), static_cast<std::size_t>(current.image_bins));
  const double j = JeffreyDivergence(p, q);
  out.raw = j;
  SetInput(*this, j, out);
}

std::optional<double> JeffreyDistance::Distance(double model_input) const {
  return InRange(options_, Cue(), options_.beta2 - options_.alpha2 * model_input);
}

void EntropyDistance::Measure(const PreparedGlance& previous, const PreparedGlance& current,
                              std::optional<double> /*travelled_m*/, DistanceMeasureResult& out) const {
  Clear(out, Cue());
  if (previous.glance.pixels == current.glance.pixels) return SetNoEstimate(out, Reason::kIdenticalFrames);
  const double dh = previous.entropy - current.entropy;
  out.raw = dh;
  if (dh == 0.0) return SetNoEstimate(out, Reason::kIdenticalFrames);
  SetInput(*this, dh, out);
}

// The paper's sign (H1 − H2) depends on whether entropy falls or rises towards the end; the
// magnitude of the change is what scales inversely with distance, so |ΔH| is used.
std::optional<double> EntropyDistance::Distance(double model_input) const {
  if (model_input == 0.0) return std::nullopt;
  return InRange(options_, Cue(), options_.alpha3 / std::abs(model_input));
}

}  // namespace squint::corridor
