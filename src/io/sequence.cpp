// The squint sequence format (SEQUENCE_FORMAT.md, version 1): reading and writing.
#include "squint/io/sequence.hpp"

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "squint/core/error.hpp"
#include "squint/io/atomic_output.hpp"
#include "squint/io/csv.hpp"
#include "yaml_camera_node.hpp"

namespace squint::io {
namespace fs = std::filesystem;

namespace {

SequenceInfo ReadInfo(const fs::path& yaml_path) {
  const std::string where = yaml_path.string();
  if (!fs::exists(yaml_path)) throw Error(where + ": missing (not a squint sequence folder?)");
  YAML::Node root;
  try {
    root = YAML::LoadFile(where);
  } catch (const YAML::Exception& e) {
    throw Error(where + ": not valid YAML (line " + std::to_string(e.mark.line + 1) + ")");
  }
  if (!root.IsMap()) throw Error(where + ": expected a YAML map");
  if (!root["format"]) throw Error(where + ": missing key 'format' (expected '" + std::string(kSequenceFormat) + "')");
  const std::string format = root["format"].as<std::string>("");
  if (format != kSequenceFormat)
    throw Error(where + ": format '" + format + "' is not supported (expected '" + kSequenceFormat + "')");
  SequenceInfo info;
  if (root["name"]) info.name = root["name"].as<std::string>("");
  if (!root["camera"]) throw Error(where + ": missing key 'camera'");
  info.camera = detail::ParseCameraNode(root["camera"], where);
  if (root["frame_rate_hz"] && !root["frame_rate_hz"].IsNull()) {
    const double r = detail::RequireDouble(root, "frame_rate_hz", where);
    if (!(r > 0.0)) throw Error(where + ": frame_rate_hz must be positive");
    info.frame_rate_hz = r;
  }
  return info;
}

std::string RowWhere(const CsvTable& t, std::size_t row) {
  return t.Path().string() + ": line " + std::to_string(t.LineOf(row));
}

}  // namespace

Sequence Sequence::Read(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw Error(dir.string() + ": not a folder");
  Sequence seq;
  seq.dir_ = dir;
  seq.info_ = ReadInfo(dir / "sequence.yaml");
  const fs::path csv_path = dir / "frames.csv";
  if (!fs::exists(csv_path)) throw Error(csv_path.string() + ": missing");
  const CsvTable t = CsvTable::Read(csv_path);
  const std::size_t c_stamp = t.Require("stamp");
  const std::size_t c_image = t.Require("image");
  const auto c_ox = t.Find("odom_x"), c_oy = t.Find("odom_y"), c_oyaw = t.Find("odom_yaw");
  const auto c_h = t.Find("gt_heading_deg"), c_l = t.Find("gt_lateral_m"), c_d = t.Find("gt_dist_end_m");
  const auto c_label = t.Find("label");
  if ((c_ox || c_oy || c_oyaw) && !(c_ox && c_oy && c_oyaw))
    throw Error(csv_path.string() + ": odometry needs all of odom_x, odom_y and odom_yaw");
  seq.frames_.reserve(t.Rows());
  for (std::size_t r = 0; r < t.Rows(); ++r) {
    FrameRecord rec;
    rec.stamp = t.RequireNumber(r, c_stamp);
    rec.image = t.Cell(r, c_image);
    if (rec.image.empty()) throw Error(RowWhere(t, r) + ": column 'image' is empty");
    if (!seq.frames_.empty() && rec.stamp < seq.frames_.back().stamp)
      throw Error(RowWhere(t, r) + ": stamp goes backwards");
    if (c_ox) {
      const auto x = t.Number(r, *c_ox), y = t.Number(r, *c_oy), yaw = t.Number(r, *c_oyaw);
      if (x && y && yaw) rec.odom = Pose2{*x, *y, *yaw};
      else if (x || y || yaw) throw Error(RowWhere(t, r) + ": odometry is partly empty");
    }
    if (c_h) rec.gt.heading_deg = t.Number(r, *c_h);
    if (c_l) rec.gt.lateral_m = t.Number(r, *c_l);
    if (c_d) rec.gt.dist_end_m = t.Number(r, *c_d);
    if (c_label) rec.label = t.Cell(r, *c_label);
    seq.frames_.push_back(std::move(rec));
  }
  if (seq.frames_.empty()) throw Error(csv_path.string() + ": no frames");
  return seq;
}

bool Sequence::HasOdometry() const {
  for (const auto& f : frames_)
    if (!f.odom) return false;
  return !frames_.empty();
}

bool Sequence::HasLabels() const {
  for (const auto& f : frames_)
    if (f.label.empty()) return false;
  return !frames_.empty();
}

namespace {
cv::Mat ReadGrey(const fs::path& path, const CameraModel& cam, const std::string& what) {
  if (!fs::exists(path)) throw Error(path.string() + ": " + what + " file is missing");
  cv::Mat img = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (img.empty()) throw Error(path.string() + ": cannot read " + what + " (unreadable or not an image)");
  if (img.depth() != CV_8U) throw Error(path.string() + ": " + what + " is not 8-bit");
  if (img.channels() == 3) cv::cvtColor(img, img, cv::COLOR_BGR2GRAY);
  else if (img.channels() == 4) cv::cvtColor(img, img, cv::COLOR_BGRA2GRAY);
  else if (img.channels() != 1) throw Error(path.string() + ": " + what + " has an unsupported number of channels");
  if (img.cols != cam.width || img.rows != cam.height) {
    std::ostringstream m;
    m << path.string() << ": " << what << " is " << img.cols << "x" << img.rows << ", the camera says " << cam.width
      << "x" << cam.height;
    throw Error(m.str());
  }
  return img;
}
}  // namespace

cv::Mat Sequence::LoadImage(std::size_t i) const {
  SQUINT_ENSURE(i < frames_.size(), "frame index out of range");
  return ReadGrey(dir_ / frames_[i].image, info_.camera, "image");
}

cv::Mat Sequence::LoadLabel(std::size_t i) const {
  SQUINT_ENSURE(i < frames_.size(), "frame index out of range");
  if (frames_[i].label.empty()) return {};
  return ReadGrey(dir_ / frames_[i].label, info_.camera, "label mask");
}

Frame Sequence::LoadFrame(std::size_t i, bool with_label) const {
  Frame f;
  f.index = i;
  f.stamp = frames_[i].stamp;
  f.image = LoadImage(i);
  f.odom = frames_[i].odom;
  f.gt = frames_[i].gt;
  if (with_label) f.label = LoadLabel(i);
  return f;
}

struct SequenceWriter::Impl {
  explicit Impl(fs::path dir) : staged(std::move(dir)) {}
  StagedDirectory staged;
  SequenceInfo info;
  bool finished = false;
};

SequenceWriter::SequenceWriter(fs::path dir, SequenceInfo info) : impl_(std::make_unique<Impl>(std::move(dir))) {
  if (auto why = info.camera.Validate(); !why.empty()) throw Error("sequence camera: " + why);
  impl_->info = std::move(info);
  fs::create_directories(impl_->staged.Path() / "images");
}

SequenceWriter::~SequenceWriter() = default;

void SequenceWriter::Add(FrameRecord record, const cv::Mat& image, const cv::Mat& label) {
  SQUINT_ENSURE(!impl_->finished, "Add after Finish");
  SQUINT_ENSURE(image.depth() == CV_8U, "sequence images must be 8-bit");
  SQUINT_ENSURE(image.cols == impl_->info.camera.width && image.rows == impl_->info.camera.height,
                "image size differs from the camera");
  SQUINT_ENSURE(records_.empty() || record.stamp >= records_.back().stamp, "stamps must not go backwards");
  char name[32];
  std::snprintf(name, sizeof name, "%06zu.png", records_.size());
  record.image = std::string("images/") + name;
  if (!cv::imwrite((impl_->staged.Path() / record.image).string(), image))
    throw Error("cannot write " + (impl_->staged.FinalPath() / record.image).string());
  record.label.clear();
  if (!label.empty()) {
    SQUINT_ENSURE(label.type() == CV_8UC1 && label.size() == image.size(), "label mask must be 8-bit, image-sized");
    fs::create_directories(impl_->staged.Path() / "labels");
    record.label = std::string("labels/") + name;
    if (!cv::imwrite((impl_->staged.Path() / record.label).string(), label))
      throw Error("cannot write " + (impl_->staged.FinalPath() / record.label).string());
  }
  records_.push_back(std::move(record));
}

void SequenceWriter::Finish() {
  SQUINT_ENSURE(!impl_->finished, "Finish called twice");
  const CameraModel& c = impl_->info.camera;
  std::ostringstream y;
  y.precision(10);
  y << "format: " << kSequenceFormat << "\n";
  y << "name: \"" << impl_->info.name << "\"\n";
  y << "camera:\n"
    << "  width: " << c.width << "\n  height: " << c.height << "\n  fx: " << c.fx << "\n  fy: " << c.fy
    << "\n  cx: " << c.cx << "\n  cy: " << c.cy << "\n  height_m: " << c.height_m << "\n  pitch_deg: " << c.pitch_deg
    << "\n";
  if (!c.distortion.empty()) {
    y << "  distortion: [";
    for (std::size_t i = 0; i < c.distortion.size(); ++i) y << (i ? ", " : "") << c.distortion[i];
    y << "]\n";
  }
  if (impl_->info.frame_rate_hz) y << "frame_rate_hz: " << *impl_->info.frame_rate_hz << "\n";
  WriteFileAtomically(impl_->staged.Path() / "sequence.yaml", y.str());

  bool any_odom = false, any_h = false, any_l = false, any_d = false, any_label = false;
  for (const auto& r : records_) {
    any_odom |= r.odom.has_value();
    any_h |= r.gt.heading_deg.has_value();
    any_l |= r.gt.lateral_m.has_value();
    any_d |= r.gt.dist_end_m.has_value();
    any_label |= !r.label.empty();
  }
  std::ostringstream f;
  f << "stamp,image";
  if (any_odom) f << ",odom_x,odom_y,odom_yaw";
  if (any_h) f << ",gt_heading_deg";
  if (any_l) f << ",gt_lateral_m";
  if (any_d) f << ",gt_dist_end_m";
  if (any_label) f << ",label";
  f << "\n";
  for (const auto& r : records_) {
    f << CsvNumber(r.stamp, 6) << "," << r.image;
    if (any_odom) {
      if (r.odom) f << "," << CsvNumber(r.odom->x, 6) << "," << CsvNumber(r.odom->y, 6) << "," << CsvNumber(r.odom->yaw, 7);
      else f << ",,,";
    }
    if (any_h) f << "," << CsvNumber(r.gt.heading_deg, 4);
    if (any_l) f << "," << CsvNumber(r.gt.lateral_m, 5);
    if (any_d) f << "," << CsvNumber(r.gt.dist_end_m, 5);
    if (any_label) f << "," << r.label;
    f << "\n";
  }
  WriteFileAtomically(impl_->staged.Path() / "frames.csv", f.str());
  impl_->staged.Commit();
  impl_->finished = true;
}

}  // namespace squint::io
