// Floor-plan drawing: free floor, walls, doors and other wall features, lights, obstacles,
// flat items and centre lines, in a BGR image with world y pointing up.
#include "squint/sim/floor_plan.hpp"

#include <opencv2/imgproc.hpp>

#include <cmath>

namespace squint::sim {

FloorPlan::FloorPlan(const World& world, const FloorPlanOptions& options) : options_(options) {
  const Box2 b = world.Bounds();
  bounds_ = {b.x0 - options.margin_m, b.y0 - options.margin_m, b.x1 + options.margin_m, b.y1 + options.margin_m};
  const int width_px = std::max(1, static_cast<int>(std::ceil((bounds_.x1 - bounds_.x0) * options.px_per_m)));
  const int height_px = std::max(1, static_cast<int>(std::ceil((bounds_.y1 - bounds_.y0) * options.px_per_m)));
  image_ = cv::Mat(height_px, width_px, CV_8UC3, cv::Scalar(60, 60, 60));
  auto fill_box = [&](const Box2& r, const cv::Scalar& c) {
    cv::rectangle(image_, ToPixel({r.x0, r.y0}), ToPixel({r.x1, r.y1}), c, cv::FILLED);
  };
  // A rectangle of half-sizes (half_x, half_y) about `centre`, turned by yaw (radians, CCW).
  auto fill_rotated = [&](const Eigen::Vector2d& centre, double half_x, double half_y, double yaw,
                          const cv::Scalar& c) {
    const cv::RotatedRect rr(ToPixel(centre), cv::Size2f(2 * half_x * options.px_per_m, 2 * half_y * options.px_per_m),
                             static_cast<float>(-yaw * 180.0 / 3.14159265358979));
    cv::Point2f pts[4];
    rr.points(pts);
    std::vector<cv::Point> poly(pts, pts + 4);
    cv::fillConvexPoly(image_, poly, c, cv::LINE_AA);
  };
  for (const Corridor& c : world.corridors) fill_box(c.rect, cv::Scalar(235, 235, 235));
  for (const Box2& r : world.recesses) fill_box(r, cv::Scalar(215, 225, 235));
  for (const FlatItem& f : world.flat_items)
    fill_rotated(f.centre, f.half_x, f.half_y, f.yaw, cv::Scalar(180, 210, 180));
  if (options.draw_lights)
    for (const Light& l : world.lights)
      fill_box({l.centre.x() - l.half_x, l.centre.y() - l.half_y, l.centre.x() + l.half_x, l.centre.y() + l.half_y},
               l.on ? cv::Scalar(120, 230, 250) : cv::Scalar(170, 170, 170));
  if (options.draw_centre_lines)
    for (const Corridor& c : world.corridors) cv::line(image_, ToPixel(c.from), ToPixel(c.to), cv::Scalar(200, 170, 150), 1, cv::LINE_AA);
  for (const WallSegment& w : world.walls) {
    const Eigen::Vector2d a = w.along_x ? Eigen::Vector2d(w.lo, w.coord) : Eigen::Vector2d(w.coord, w.lo);
    const Eigen::Vector2d b2 = w.along_x ? Eigen::Vector2d(w.hi, w.coord) : Eigen::Vector2d(w.coord, w.hi);
    const double mirror = world.materials[w.material].mirror;
    cv::line(image_, ToPixel(a), ToPixel(b2), mirror > 0 ? cv::Scalar(200, 120, 0) : cv::Scalar(20, 20, 20), 2, cv::LINE_AA);
  }
  for (const Decal& d : world.decals) {
    const WallSegment& w = world.walls[d.wall];
    const Eigen::Vector2d a = w.along_x ? Eigen::Vector2d(d.lo, w.coord) : Eigen::Vector2d(w.coord, d.lo);
    const Eigen::Vector2d b2 = w.along_x ? Eigen::Vector2d(d.hi, w.coord) : Eigen::Vector2d(w.coord, d.hi);
    const Material& m = world.materials[d.material];
    cv::Scalar colour(40, 90, 160);                                   // doors: brown
    if (m.texture == Texture::kPoster) colour = cv::Scalar(160, 40, 160);
    if (m.texture == Texture::kGlass || m.texture == Texture::kWindow) colour = cv::Scalar(230, 200, 60);
    if (m.mirror > 0) colour = cv::Scalar(200, 120, 0);
    cv::line(image_, ToPixel(a), ToPixel(b2), colour, 3, cv::LINE_AA);
  }
  for (const Obstacle& o : world.obstacles) {
    if (o.shape == Obstacle::Shape::kCylinder) {
      cv::circle(image_, ToPixel(o.centre), std::max(1, static_cast<int>(o.radius * options.px_per_m)), cv::Scalar(40, 40, 200),
                 cv::FILLED, cv::LINE_AA);
    } else {
      fill_rotated(o.centre, o.half_x, o.half_y, o.yaw, cv::Scalar(40, 40, 200));
    }
  }
  DrawRobot(world.start, world.robot.radius_m, cv::Scalar(0, 160, 0));
}

cv::Point2d FloorPlan::ToPixel(const Eigen::Vector2d& p) const {
  return {(p.x() - bounds_.x0) * options_.px_per_m, (bounds_.y1 - p.y()) * options_.px_per_m};
}

void FloorPlan::DrawPath(const std::vector<Pose2>& poses, const cv::Scalar& bgr, int thickness) {
  for (std::size_t i = 1; i < poses.size(); ++i)
    cv::line(image_, ToPixel(poses[i - 1].Translation()), ToPixel(poses[i].Translation()), bgr, thickness, cv::LINE_AA);
}

void FloorPlan::DrawRobot(const Pose2& pose, double radius_m, const cv::Scalar& bgr) {
  const cv::Point2d c = ToPixel(pose.Translation());
  cv::circle(image_, c, std::max(2, static_cast<int>(radius_m * options_.px_per_m)), bgr, 1, cv::LINE_AA);
  const Eigen::Vector2d tip = pose.Translation() + 1.5 * radius_m * Eigen::Vector2d(std::cos(pose.yaw), std::sin(pose.yaw));
  cv::line(image_, c, ToPixel(tip), bgr, 1, cv::LINE_AA);
}

}  // namespace squint::sim
