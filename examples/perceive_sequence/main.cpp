// Example: fused corridor heading and distance-to-end for every frame of a sequence folder.
// Build: cmake -S examples/perceive_sequence -B ex -DCMAKE_PREFIX_PATH=<squint install prefix>
#include <cstdio>
#include <exception>

#include "squint/core/error.hpp"
#include "squint/corridor/perceiver.hpp"
#include "squint/io/frame_source.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s SEQUENCE_OR_VIDEO\n", argv[0]);
    return 2;
  }
  try {
    auto source = squint::io::OpenFrameSource(argv[1]);
    squint::corridor::Perceiver perceiver({}, source->Camera());
    std::optional<squint::io::Frame> previous;
    while (auto frame = source->Next()) {
      const cv::Mat& img = frame->image;  // 8-bit grey
      const squint::GrayView view{img.data, img.cols, img.rows, static_cast<std::ptrdiff_t>(img.step)};
      std::optional<double> travelled;
      if (previous && previous->odom && frame->odom)
        travelled = (frame->odom->Translation() - previous->odom->Translation()).norm();
      const double dt = previous ? frame->stamp - previous->stamp : 0.0;
      const auto r = perceiver.Process(view, travelled, dt);
      std::printf("%.3f heading %s deg, end %s m\n", frame->stamp,
                  r.heading_deg ? std::to_string(*r.heading_deg).c_str() : "-",
                  r.dist_end_m ? std::to_string(*r.dist_end_m).c_str() : "-");
      previous = std::move(frame);
    }
  } catch (const squint::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}
