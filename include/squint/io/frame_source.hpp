// Frame sources: a sequence folder, an image folder or a video file, all yielding Frames.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "squint/core/camera.hpp"
#include "squint/io/sequence.hpp"

namespace squint::io {

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // The next frame, or none at the end. Throws squint::Error for an unreadable frame.
  virtual std::optional<Frame> Next() = 0;
  // The camera when the input declares one (sequences do; videos and image folders do not).
  virtual std::optional<CameraModel> Camera() const = 0;
  // Number of frames when known in advance.
  virtual std::optional<std::size_t> Count() const = 0;
  virtual std::string Describe() const = 0;
};

struct FrameSourceOptions {
  // Frame rate assumed for image folders (stamp = index / rate) and for videos that report none.
  double default_frame_rate_hz = 30.0;
};

// Opens INPUT: a folder with sequence.yaml is a sequence; another folder is an image folder
// (*.png, *.jpg, *.jpeg, *.bmp, *.pgm, *.ppm, *.tif, *.tiff in name order); a file is a video
// opened through OpenCV. Throws squint::Error when it does not exist or cannot be opened.
std::unique_ptr<FrameSource> OpenFrameSource(const std::filesystem::path& input,
                                             const FrameSourceOptions& options = {});

}  // namespace squint::io
