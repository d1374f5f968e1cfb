// The ceiling lights' line in a small frame (the 32×24 glance): where the robot stands across the
// corridor and how it is turned, from the lights alone.
//
// Paper §4.1.5 takes the median column of the bright pixels as the corridor's centre and notes
// that ceiling lights move with translation, so they can keep the robot centred. This is the
// geometric form of that remark. A row of lights runs along the corridor at a height H above the
// camera. A pixel of it, with robot-frame ray (x forward, y left, z up), lies on the ceiling plane
// at (x/z, y/z) · H, so in units of H the light row is the line  a = c0 + c1 · b  with b = x/z
// (along) and a = y/z (across). c0 is the row's lateral offset over H at the robot (left positive),
// c1 the tangent of its direction (left positive). Each image row above the horizon gives one
// point: the centroid of its one light peak (a centre row of lights), or the midpoint of its two
// peaks (two side rows, symmetric about the centre line: points at one depth project affinely, so
// their image midpoint is the midpoint's image). A straight-line fit over at least min_rows rows
// gives c0 and c1; H only scales the offset into metres (nominal_height_m).
#pragma once

#include <string>

#include "squint/core/camera.hpp"
#include "squint/core/image_view.hpp"

namespace squint::explore {

struct LightLineOptions {
  int min_level = 150;          // a light peak is at least this bright...
  int min_contrast = 30;        // ...and this much brighter than the pixels two columns away,
  double min_relative_contrast = 0.3;  // ...by at least this fraction of its level,
  int max_side_difference = 20;  // ...which differ from each other by at most this (the ceiling)
  int min_rows = 3;             // image rows with a light point needed for a fit
  double min_span = 1.5;        // spread of the rows' along coordinate b (units of H) needed
  double max_residual_px = 0.8;  // largest residual of a kept fit, as image columns at the row's depth
  double nominal_height_m = 2.2;  // the lights' height above the camera assumed for metres
  bool side_rows = false;       // also fit two side rows by their midpoints (not reliable yet)
  int max_multi_peak_rows = 0;  // a centre-row fit only where at most this many rows show several peaks
  std::string Validate() const;
};

struct LightLine {
  bool valid = false;
  int rows = 0;             // image rows used
  bool side_rows = false;   // two peaks per row (two side rows of lights)
  double offset_ratio = 0.0;  // c0: the light line's lateral offset at the robot over H, left positive
  double direction_rad = 0.0;  // atan(c1): the line's direction in the robot frame, left positive
  double residual_px = 0.0;  // largest absolute residual of the fit (image columns)
  // The robot's lateral position from the light line in metres (left positive), the lights being
  // height_m above the camera: −c0 · H cos(direction).
  double LateralM(double height_m) const;
};

// The light line in `image`, whose camera is `camera` (same size). Invalid when fewer than
// min_rows rows hold a light point, the rows span too little depth, or the fit's residual is too
// large (lights of a crossing corridor, a lit wall).
LightLine FindLightLine(const GrayView& image, const CameraModel& camera, const LightLineOptions& options = {});

}  // namespace squint::explore
