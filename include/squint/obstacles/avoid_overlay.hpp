// Drawings of the avoidance stage like the obstacle paper's Figs 12–15: the image with obstacle
// (red) and ground (blue) features, the edge map with obstacle outlines (orange) and contact
// points within the ROI (pink), and the polar occupancy map with the steering vector (green).
#pragma once

#include <span>

#include <opencv2/core.hpp>

#include "squint/obstacles/avoider.hpp"

namespace squint::obstacles {

// One BGR panel strip: [image + features + outlines + contacts | edge map + outlines + contacts |
// polar map]. `gray` is the image Process() saw; `scale` enlarges the image panels.
cv::Mat DrawAvoidOverlay(const cv::Mat& gray, std::span<const ClassifiedFeature> features, const AvoidResult& result,
                         int scale = 2);

// The polar map alone: a bird's-eye semicircle of the ROI (robot at the bottom centre, left
// to the left), sectors shaded free / occupied / unseen, contact points in pink, and the
// steering vector in green (or "STOP"). `size_px` is the panel height; the width is twice it.
cv::Mat DrawPolarMap(const PolarMap& map, std::span<const ContactPoint> contacts, const SteeringDecision& decision,
                     int size_px = 384);

}  // namespace squint::obstacles
