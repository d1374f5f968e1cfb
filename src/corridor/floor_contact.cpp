// Floor contact of the end wall: the first grey-level edge below the horizon in the centre
// columns, back-projected onto the floor through the camera model.
#include "squint/corridor/floor_contact.hpp"

#include <algorithm>
#include <cmath>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/core/median.hpp"

namespace squint::corridor {

std::string FloorContact::CameraProblem(const CameraModel& camera) {
  if (!camera.HasIntrinsics() || camera.width < 3 || camera.height < 4 || !(camera.height_m > 0.0))
    return "the camera needs intrinsics and a height above the floor";
  const double horizon = camera.HorizonRow();
  if (!(horizon > -1.0 && horizon < camera.height - 3)) return "the horizon is not inside the frame (check the camera pitch)";
  return {};
}

FloorContact::FloorContact(const CameraModel& camera, const FloorContactOptions& options)
    : camera_(camera), options_(options) {
  if (std::string e = options_.Validate(); !e.empty()) throw Error("floor contact: " + e);
  if (std::string e = CameraProblem(camera_); !e.empty()) throw Error("floor contact: " + e);
  top_row_ = std::max(0, static_cast<int>(std::ceil(camera_.HorizonRow())));
  const double half = camera_.fx * std::tan(DegToRad(options_.half_width_deg));
  u_first_ = std::max(1, static_cast<int>(std::lround(camera_.cx - half)));
  u_last_ = std::min(camera_.width - 2, static_cast<int>(std::lround(camera_.cx + half)));
  profile_.assign(static_cast<std::size_t>(camera_.height), 0.0);
  readings_.reserve(static_cast<std::size_t>(std::max(0, u_last_ - u_first_ + 1)));
  rows_.reserve(readings_.capacity());
}

std::optional<double> FloorContact::BoundaryRow(const PixelView& frame, int u) {
  const int h = camera_.height;
  for (int v = top_row_; v < h; ++v) profile_[static_cast<std::size_t>(v)] = ColumnGrey(frame, u, v);
  const std::optional<double> first = EdgeRow(options_.min_step);
  if (!first || !(options_.lined_wall_rel_step > 0.0) || !LinedAbove(frame, u, *first)) return first;
  lined_ = true;
  // A lined wall: the first step that is a fair share of the column's strongest below the horizon.
  double strongest = 0.0;
  for (int v = top_row_ + 1; v < h - 2; ++v) strongest = std::max(strongest, Step(v));
  return EdgeRow(std::max(options_.min_step, options_.lined_wall_rel_step * strongest));
}

double FloorContact::ColumnGrey(const PixelView& frame, int u, int v) const {
  const std::uint8_t* row = frame.data + static_cast<std::ptrdiff_t>(v) * frame.stride;
  return (GreyAt(row, u - 1, frame.channels) + GreyAt(row, u, frame.channels) + GreyAt(row, u + 1, frame.channels)) / 3.0;
}

double FloorContact::Step(int v) const {
  return std::abs(profile_[static_cast<std::size_t>(v + 1)] - profile_[static_cast<std::size_t>(v)]);
}

bool FloorContact::LinedAbove(const PixelView& frame, int u, double edge_row) const {
  // The rows from Δ above the horizon up to the last one above it (top_row_ − 1), Δ the edge's
  // depth below the horizon.
  const double horizon = camera_.HorizonRow();
  const int lo = std::max(0, static_cast<int>(std::floor(horizon - (edge_row - horizon))));
  double prev = 0.0;
  for (int v = lo; v < top_row_; ++v) {
    const double g = ColumnGrey(frame, u, v);
    if (v > lo && std::abs(g - prev) >= options_.min_step) return true;
    prev = g;
  }
  return false;
}

std::optional<double> FloorContact::EdgeRow(double min_step) const {
  const int h = camera_.height;
  // Step(v) = |p(v + 1) - p(v)|: the edge between rows v and v + 1.
  // The signed change p(v + 1) - p(v) times `sign`.
  auto signed_step = [&](int v, double sign) {
    return sign * (profile_[static_cast<std::size_t>(v + 1)] - profile_[static_cast<std::size_t>(v)]);
  };
  for (int v = top_row_ + 1; v < h - 2; ++v) {
    if (Step(v) < min_step) continue;
    int best = v;
    if (options_.refine_same_sign) {
      // Only changes of the first one's sign, up to the first of the other sign (the far side of
      // a thin line is not the edge).
      const double sign = signed_step(v, 1.0) > 0.0 ? 1.0 : -1.0;
      for (int j = v + 1; j < std::min(v + 3, h - 2); ++j) {
        if (!(signed_step(j, sign) > 0.0)) break;
        if (Step(j) > Step(best)) best = j;
      }
      double off = 0.0;
      if (best > top_row_ && best + 1 < h - 1) {
        const double a = std::max(0.0, signed_step(best - 1, sign)), b = signed_step(best, sign),
                     c = std::max(0.0, signed_step(best + 1, sign));
        const double den = a - 2.0 * b + c;
        if (den != 0.0) off = std::clamp(0.5 * (a - c) / den, -0.5, 0.5);
      }
      return best + 0.5 + off;
    }
    for (int j = v + 1; j < std::min(v + 3, h - 2); ++j)
      if (Step(j) > Step(best)) best = j;
    double off = 0.0;
    if (best > top_row_ && best + 1 < h - 1) {
      const double a = Step(best - 1), b = Step(best), c = Step(best + 1);
      const double den = a - 2.0 * b + c;
      if (den != 0.0) off = std::clamp(0.5 * (a - c) / den, -0.5, 0.5);
    }
    return best + 0.5 + off;
  }
  return std::nullopt;
}

std::optional<double> FloorContact::Measure(const PixelView& frame) {
  if (frame.data == nullptr || frame.width != camera_.width || frame.height != camera_.height) return std::nullopt;
  readings_.clear();
  rows_.clear();
  lined_ = false;
  const int columns = u_last_ - u_first_ + 1;
  if (columns <= 0) return std::nullopt;
  for (int u = u_first_; u <= u_last_; ++u) {
    const std::optional<double> y = BoundaryRow(frame, u);
    if (!y) continue;
    rows_.push_back(*y);
    const std::optional<Eigen::Vector2d> fp = camera_.FloorPoint({static_cast<double>(u), *y});
    if (!fp || !std::isfinite(fp->x()) || fp->x() <= 0.0) continue;
    readings_.push_back(fp->x());
  }
  if (static_cast<double>(readings_.size()) < options_.min_column_fraction * columns || readings_.empty()) return std::nullopt;
  if (lined_) {
    // Where the lined-wall rule searched again, the foot must be one line across the columns: at
    // least min_column_fraction of them within kLinedWallRowSpread of their median row.
    const double mid = MedianInPlace(rows_);
    const auto on_line = std::count_if(rows_.begin(), rows_.end(), [&](double y) { return std::abs(y - mid) <= kLinedWallRowSpread; });
    if (static_cast<double>(on_line) < options_.min_column_fraction * columns) return std::nullopt;
  }
  const double med = MedianInPlace(readings_);
  if (!(med >= options_.min_m && med <= options_.max_m)) return std::nullopt;
  return med;
}

FloorMotionCheck::FloorMotionCheck(const CameraModel& camera, const FloorContactOptions& options)
    : camera_(camera), options_(options) {
  if (std::string e = options_.Validate(); !e.empty()) throw Error("floor contact: " + e);
  if (std::string e = FloorContact::CameraProblem(camera_); !e.empty()) throw Error("floor contact: " + e);
}

void FloorMotionCheck::Reset() { head_ = count_ = 0; }

double FloorMotionCheck::FloorRow(double dist_m) const {
  // The ray to the floor point dips atan(h / d) below the horizontal; the optical axis is
  // pitched by pitch_deg (negative: down), so at d → ∞ this is CameraModel::HorizonRow().
  return camera_.cy + camera_.fy * std::tan(std::atan2(camera_.height_m, dist_m) + DegToRad(camera_.pitch_deg));
}

bool FloorMotionCheck::Update(double travel_m, std::optional<double> reading) {
  constexpr int kCap = kMaxFloorMotionReadings;
  if (!reading) return false;
  head_ = (head_ + 1) % kCap;
  travel_[static_cast<std::size_t>(head_)] = travel_m;
  reading_[static_cast<std::size_t>(head_)] = *reading;
  row_[static_cast<std::size_t>(head_)] = FloorRow(*reading);
  count_ = std::min(count_ + 1, kCap);
  // The readings within the window, newest first.
  int n = 0;
  double oldest_travel = travel_m;
  for (int k = 0; k < count_; ++k) {
    const auto idx = static_cast<std::size_t>(((head_ - k) % kCap + kCap) % kCap);
    if (travel_m - travel_[idx] > options_.motion_window_m) break;
    scratch_[static_cast<std::size_t>(n++)] = travel_[idx] + reading_[idx];
    oldest_travel = travel_[idx];
  }
  if (n < options_.motion_min_readings || travel_m - oldest_travel < 0.5 * options_.motion_window_m) return false;
  const double end = MedianInPlace(std::span<double>(scratch_.data(), static_cast<std::size_t>(n)));
  // A test that an edge fixed in the image passes as well says nothing: over the window's travel
  // the floor point must cross more than motion_tol_rows (far away, or over a short window, it
  // does not; a wall's course at the camera's height reads farther than 15 m and stays put).
  if (!(end - travel_m > 0.0) || FloorRow(end - travel_m) - FloorRow(end - oldest_travel) <= options_.motion_tol_rows)
    return false;
  int inliers = 0;
  for (int k = 0; k < n; ++k) {
    const auto idx = static_cast<std::size_t>(((head_ - k) % kCap + kCap) % kCap);
    const double predicted = end - travel_[idx];
    if (predicted > 0.0 && std::abs(row_[idx] - FloorRow(predicted)) <= options_.motion_tol_rows) ++inliers;
  }
  return inliers >= options_.motion_min_fraction * n;
}

}  // namespace squint::corridor
