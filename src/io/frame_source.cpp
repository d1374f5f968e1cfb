// Frame sources over sequence folders, image folders and video files.
#include "squint/io/frame_source.hpp"

#include <algorithm>
#include <cctype>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <vector>

#include "squint/core/error.hpp"

namespace squint::io {
namespace fs = std::filesystem;

namespace {

class SequenceSource : public FrameSource {
 public:
  explicit SequenceSource(Sequence seq) : seq_(std::move(seq)) {}
  std::optional<Frame> Next() override {
    if (next_ >= seq_.Size()) return std::nullopt;
    return seq_.LoadFrame(next_++);
  }
  std::optional<CameraModel> Camera() const override { return seq_.Camera(); }
  std::optional<std::size_t> Count() const override { return seq_.Size(); }
  std::string Describe() const override { return "sequence " + seq_.Dir().string(); }

 private:
  Sequence seq_;
  std::size_t next_ = 0;
};

bool IsImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  static const char* kExt[] = {".png", ".jpg", ".jpeg", ".bmp", ".pgm", ".ppm", ".tif", ".tiff"};
  return std::any_of(std::begin(kExt), std::end(kExt), [&](const char* e) { return ext == e; });
}

cv::Mat ToGrey(cv::Mat img, const std::string& where) {
  if (img.depth() != CV_8U) throw Error(where + ": not an 8-bit image");
  if (img.channels() == 3) cv::cvtColor(img, img, cv::COLOR_BGR2GRAY);
  else if (img.channels() == 4) cv::cvtColor(img, img, cv::COLOR_BGRA2GRAY);
  else if (img.channels() != 1) throw Error(where + ": unsupported number of channels");
  return img;
}

class ImageFolderSource : public FrameSource {
 public:
  ImageFolderSource(fs::path dir, double rate) : dir_(std::move(dir)), rate_(rate) {
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.is_regular_file() && IsImageFile(e.path())) files_.push_back(e.path());
    std::sort(files_.begin(), files_.end());
    if (files_.empty()) throw Error(dir_.string() + ": folder holds no images and no sequence.yaml");
  }
  std::optional<Frame> Next() override {
    if (next_ >= files_.size()) return std::nullopt;
    const fs::path& p = files_[next_];
    cv::Mat img = cv::imread(p.string(), cv::IMREAD_UNCHANGED);
    if (img.empty()) throw Error(p.string() + ": cannot read image");
    img = ToGrey(img, p.string());
    if (size_.width == 0) size_ = img.size();
    else if (img.size() != size_) throw Error(p.string() + ": image size differs from the folder's first image");
    Frame f;
    f.index = next_;
    f.stamp = static_cast<double>(next_) / rate_;
    f.image = img;
    ++next_;
    return f;
  }
  std::optional<CameraModel> Camera() const override { return std::nullopt; }
  std::optional<std::size_t> Count() const override { return files_.size(); }
  std::string Describe() const override { return "image folder " + dir_.string(); }

 private:
  fs::path dir_;
  double rate_;
  std::vector<fs::path> files_;
  std::size_t next_ = 0;
  cv::Size size_;
};

class VideoSource : public FrameSource {
 public:
  VideoSource(fs::path path, double default_rate) : path_(std::move(path)) {
    if (!OpenQuietly()) throw Error(path_.string() + ": cannot open video");
    const double fps = cap_.get(cv::CAP_PROP_FPS);
    rate_ = fps > 0.0 && std::isfinite(fps) ? fps : default_rate;
    const double n = cap_.get(cv::CAP_PROP_FRAME_COUNT);
    if (n > 0 && std::isfinite(n)) count_ = static_cast<std::size_t>(n);
  }
  // FFmpeg first, then any other backend; their own complaints about a file they cannot open
  // (several lines each) are silenced, since the caller reports the failure in one line.
  bool OpenQuietly() {
    namespace logging = cv::utils::logging;
    const logging::LogLevel level = logging::getLogLevel();
    logging::setLogLevel(logging::LOG_LEVEL_SILENT);
    const bool ok = cap_.open(path_.string(), cv::CAP_FFMPEG) || cap_.open(path_.string(), cv::CAP_ANY);
    logging::setLogLevel(level);
    return ok;
  }

  std::optional<Frame> Next() override {
    cv::Mat img;
    if (!cap_.read(img) || img.empty()) return std::nullopt;
    Frame f;
    f.index = next_;
    f.stamp = static_cast<double>(next_) / rate_;
    f.image = ToGrey(img, path_.string() + ": frame " + std::to_string(next_));
    ++next_;
    return f;
  }
  std::optional<CameraModel> Camera() const override { return std::nullopt; }
  std::optional<std::size_t> Count() const override { return count_; }
  std::string Describe() const override { return "video " + path_.string(); }

 private:
  fs::path path_;
  cv::VideoCapture cap_;
  double rate_ = 30.0;
  std::optional<std::size_t> count_;
  std::size_t next_ = 0;
};

}  // namespace

std::unique_ptr<FrameSource> OpenFrameSource(const fs::path& input, const FrameSourceOptions& options) {
  if (!(options.default_frame_rate_hz > 0.0)) throw Error("frame rate must be positive");
  if (!fs::exists(input)) throw Error(input.string() + ": no such file or folder");
  if (fs::is_directory(input)) {
    if (fs::exists(input / "sequence.yaml")) return std::make_unique<SequenceSource>(Sequence::Read(input));
    // A sequence folder without its camera file is a broken sequence, not an image folder.
    if (fs::exists(input / "frames.csv"))
      throw Error((input / "sequence.yaml").string() + ": missing (the folder has frames.csv, so it is a sequence)");
    return std::make_unique<ImageFolderSource>(input, options.default_frame_rate_hz);
  }
  return std::make_unique<VideoSource>(input, options.default_frame_rate_hz);
}

}  // namespace squint::io
