// The squint sequence format (SEQUENCE_FORMAT.md, version 1): reader and writer.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "squint/core/camera.hpp"
#include "squint/core/ground_truth.hpp"
#include "squint/core/pose.hpp"

namespace squint::io {

inline constexpr const char* kSequenceFormat = "squint-sequence/1";

struct SequenceInfo {
  std::string name;
  CameraModel camera;
  std::optional<double> frame_rate_hz;
};

// One row of frames.csv. Paths are relative to the sequence folder.
struct FrameRecord {
  double stamp = 0.0;
  std::string image;
  std::optional<Pose2> odom;  // world_T_robot in the odometry frame
  GroundTruth gt;
  std::string label;  // empty = no label mask
};

// One frame as everything downstream of the readers sees it (DESIGN.md `Frame`).
struct Frame {
  std::size_t index = 0;  // 0-based position in the input
  double stamp = 0.0;
  cv::Mat image;  // 8-bit, grey or BGR as read
  std::optional<Pose2> odom;
  GroundTruth gt;
  cv::Mat label;  // 8-bit mask or empty
};

class Sequence {
 public:
  // Reads sequence.yaml and frames.csv (images are loaded on demand). Throws squint::Error
  // naming the file (and row) for a missing file, a wrong `format`, a missing required
  // column, a non-numeric or truncated row, or stamps that go backwards.
  static Sequence Read(const std::filesystem::path& dir);

  const std::filesystem::path& Dir() const { return dir_; }
  const SequenceInfo& Info() const { return info_; }
  const CameraModel& Camera() const { return info_.camera; }
  const std::vector<FrameRecord>& Frames() const { return frames_; }
  std::size_t Size() const { return frames_.size(); }
  bool HasOdometry() const;   // every row has odom_x, odom_y and odom_yaw
  bool HasLabels() const;     // every row names a label mask

  // Loads an image as 8-bit grey (colour images are converted). Throws squint::Error naming the
  // file when it is missing, unreadable, or not of the camera's size.
  cv::Mat LoadImage(std::size_t i) const;
  // Loads the label mask (8-bit, 0 floor / 255 standing); empty when the row has none.
  cv::Mat LoadLabel(std::size_t i) const;
  Frame LoadFrame(std::size_t i, bool with_label = false) const;

 private:
  std::filesystem::path dir_;
  SequenceInfo info_;
  std::vector<FrameRecord> frames_;
};

// Writes a sequence into a staging folder and moves it into place on Finish(); an unfinished
// writer leaves nothing behind. Images go to images/NNNNNN.png and masks to labels/NNNNNN.png.
// Optional columns are written when any frame has them (empty cells elsewhere).
class SequenceWriter {
 public:
  SequenceWriter(std::filesystem::path dir, SequenceInfo info);
  ~SequenceWriter();
  SequenceWriter(const SequenceWriter&) = delete;
  SequenceWriter& operator=(const SequenceWriter&) = delete;

  // `record.image` and `record.label` are filled in by the writer.
  void Add(FrameRecord record, const cv::Mat& image, const cv::Mat& label = cv::Mat());
  std::size_t Size() const { return records_.size(); }
  void Finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<FrameRecord> records_;
};

}  // namespace squint::io
