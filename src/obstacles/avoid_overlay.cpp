// Drawings of the avoidance stage (obstacle paper Figs 12–15).
#include "squint/obstacles/avoid_overlay.hpp"

#include <cmath>
#include <string>

#include <opencv2/imgproc.hpp>

#include "squint/core/angles.hpp"

namespace squint::obstacles {

namespace {
const cv::Scalar kRed(0, 0, 255), kBlue(255, 80, 0), kOrange(0, 140, 255), kPink(203, 102, 255), kGreen(0, 200, 0),
    kGrey(128, 128, 128), kWhite(255, 255, 255);

cv::Point Scaled(const Eigen::Vector2d& px, int scale) {
  return {static_cast<int>(std::lround((px.x() + 0.5) * scale - 0.5)),
          static_cast<int>(std::lround((px.y() + 0.5) * scale - 0.5))};
}

void DrawOutlinesAndContacts(cv::Mat& bgr, const AvoidResult& r, double roi_m, int scale) {
  for (const Eigen::Vector2i& p : *r.outline_pixels)
    cv::rectangle(bgr, cv::Rect(p.x() * scale, p.y() * scale, scale, scale), kOrange, cv::FILLED);
  for (const ContactPoint& c : r.contacts) {
    const bool in_roi = c.range_m <= roi_m && c.bearing_deg >= -90.0 && c.bearing_deg <= 90.0;
    cv::circle(bgr, Scaled(c.pixel, scale), in_roi ? 3 * scale / 2 + 1 : scale, in_roi ? kPink : kGrey, cv::FILLED,
               cv::LINE_AA);
  }
}
}  // namespace

cv::Mat DrawPolarMap(const PolarMap& map, std::span<const ContactPoint> contacts, const SteeringDecision& decision,
                     int size_px) {
  const int w = 2 * size_px, h = size_px;
  cv::Mat panel(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Point2d origin(w / 2.0, h - 12.0);
  const double px_per_m = (h - 24.0) / map.roi_radius_m;
  // Floor point (x forward, y left) -> panel pixel (forward up, left to the left).
  auto to_panel = [&](double x, double y) { return cv::Point(cvRound(origin.x - y * px_per_m), cvRound(origin.y - x * px_per_m)); };
  for (const PolarSector& s : map.sectors) {
    std::vector<cv::Point> poly = {to_panel(0, 0)};
    for (double a = s.start_deg; a <= s.end_deg + 1e-9; a += 1.0)
      poly.push_back(to_panel(map.roi_radius_m * std::cos(DegToRad(a)), map.roi_radius_m * std::sin(DegToRad(a))));
    // Free with floor seen (ground features in the ROI) green; free only for want of contacts
    // pale green; occupied red; unseen grey.
    const cv::Scalar fill = s.state == SectorState::kOccupied ? cv::Scalar(170, 170, 255)
                            : s.state == SectorState::kFree   ? (s.ground > 0 ? cv::Scalar(190, 240, 190)
                                                                              : cv::Scalar(228, 242, 228))
                                                              : cv::Scalar(225, 225, 225);
    cv::fillConvexPoly(panel, poly, fill, cv::LINE_AA);
    cv::polylines(panel, poly, true, cv::Scalar(190, 190, 190), 1, cv::LINE_AA);
    if (s.state == SectorState::kOccupied && s.range_m) {
      // The nearest contact as an arc across the sector.
      std::vector<cv::Point> arc;
      for (double a = s.start_deg; a <= s.end_deg + 1e-9; a += 1.0)
        arc.push_back(to_panel(*s.range_m * std::cos(DegToRad(a)), *s.range_m * std::sin(DegToRad(a))));
      cv::polylines(panel, arc, false, kRed, 2, cv::LINE_AA);
    }
  }
  for (double r = 0.5; r < map.roi_radius_m + 1e-9; r += 0.5)
    cv::ellipse(panel, origin, cv::Size(cvRound(r * px_per_m), cvRound(r * px_per_m)), 0, 180, 360, kGrey, 1,
                cv::LINE_AA);
  for (const ContactPoint& c : contacts)
    if (c.range_m <= map.roi_radius_m && c.floor_m.x() >= 0)
      cv::circle(panel, to_panel(c.floor_m.x(), c.floor_m.y()), 4, kPink, cv::FILLED, cv::LINE_AA);
  if (decision.steer_deg) {
    const double a = DegToRad(*decision.steer_deg);
    cv::arrowedLine(panel, to_panel(0, 0), to_panel(map.roi_radius_m * std::cos(a), map.roi_radius_m * std::sin(a)),
                    kGreen, 3, cv::LINE_AA, 0, 0.06);
    cv::putText(panel, cv::format("steer %+.1f deg", *decision.steer_deg), {8, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.6,
                cv::Scalar(0, 120, 0), 1, cv::LINE_AA);
  } else {
    cv::putText(panel, "STOP", {8, 26}, cv::FONT_HERSHEY_SIMPLEX, 0.8, kRed, 2, cv::LINE_AA);
  }
  cv::putText(panel, cv::format("ROI %.1f m, %g deg sectors", map.roi_radius_m, map.sector_deg), {w - 230, 22},
              cv::FONT_HERSHEY_SIMPLEX, 0.45, kGrey, 1, cv::LINE_AA);
  return panel;
}

cv::Mat DrawAvoidOverlay(const cv::Mat& gray, std::span<const ClassifiedFeature> features, const AvoidResult& r,
                         int scale) {
  scale = std::max(1, scale);
  cv::Mat big;
  cv::resize(gray, big, cv::Size(), scale, scale, cv::INTER_NEAREST);
  cv::Mat left;
  cv::cvtColor(big, left, cv::COLOR_GRAY2BGR);
  const double roi_m = r.map ? r.map->roi_radius_m : 0.0;
  DrawOutlinesAndContacts(left, r, roi_m, scale);
  for (const ClassifiedFeature& f : features)
    cv::circle(left, Scaled(f.pixel, scale), 2 + scale / 2, f.cls == FeatureClass::kObstacle ? kRed : kBlue, cv::FILLED,
               cv::LINE_AA);

  cv::Mat edges_big, middle;
  cv::Mat both = *r.edges / 3;  // dim, so that the outlines stand out
  if (r.base_edges && !r.base_edges->empty()) both = cv::max(both, *r.base_edges / 5);  // horizontal edges dimmer
  cv::resize(both, edges_big, cv::Size(), scale, scale, cv::INTER_NEAREST);
  cv::cvtColor(edges_big, middle, cv::COLOR_GRAY2BGR);
  DrawOutlinesAndContacts(middle, r, roi_m, scale);

  cv::Mat polar = DrawPolarMap(*r.map, r.contacts, r.decision, left.rows);
  cv::Mat out;
  cv::hconcat(std::vector<cv::Mat>{left, middle, polar}, out);
  return out;
}

}  // namespace squint::obstacles
