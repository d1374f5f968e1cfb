// Descriptor matching of the feature trackers against OpenCV's reference (BFMatcher knnMatch with
// k = 2, ratio test, mutual best match), on a textured image and a zoomed copy of it.
#include "squint/obstacles/feature_tracker.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <tuple>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

namespace squint::obstacles {
namespace {

cv::Mat TexturedImage() {
  cv::Mat small(48, 64, CV_8U);
  cv::RNG rng(3);
  rng.fill(small, cv::RNG::UNIFORM, 0, 256);
  cv::Mat image;
  cv::resize(small, image, cv::Size(256, 192), 0, 0, cv::INTER_CUBIC);
  return image;
}

// The later frame: the earlier one zoomed by 3% about a point below the centre (forward motion).
cv::Mat Zoomed(const cv::Mat& image) {
  const cv::Mat m = cv::getRotationMatrix2D(cv::Point2f(128.f, 120.f), 0.0, 1.03);
  cv::Mat out;
  cv::warpAffine(image, out, m, image.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  return out;
}

using PointPair = std::tuple<float, float, float, float>;

std::vector<PointPair> Reference(const cv::Ptr<cv::Feature2D>& feature, int norm, const cv::Mat& a, const cv::Mat& b,
                                 const FeatureOptions& o) {
  std::vector<cv::KeyPoint> ka, kb;
  cv::Mat da, db;
  feature->detectAndCompute(a, cv::noArray(), ka, da);
  feature->detectAndCompute(b, cv::noArray(), kb, db);
  cv::BFMatcher matcher(norm);
  std::vector<std::vector<cv::DMatch>> knn;
  std::vector<cv::DMatch> back;
  matcher.knnMatch(db, da, knn, 2);
  matcher.match(da, db, back);
  std::vector<PointPair> out;
  for (const auto& pair : knn) {
    if (pair.size() < 2 || !(pair[0].distance < o.ratio * pair[1].distance)) continue;
    if (back[static_cast<std::size_t>(pair[0].trainIdx)].trainIdx != pair[0].queryIdx) continue;
    const cv::Point2f p = ka[static_cast<std::size_t>(pair[0].trainIdx)].pt;
    const cv::Point2f c = kb[static_cast<std::size_t>(pair[0].queryIdx)].pt;
    if (cv::norm(p - c) > o.max_displacement_px) continue;
    out.emplace_back(p.x, p.y, c.x, c.y);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The upright ORB reference: OpenCV's ORB with FAST_SCORE, its keypoints level by level and row by
// row, every angle set to 0, and ORB's descriptors of those keypoints computed on its whole pyramid
// (ORB::compute).
class UprightOrbReference : public cv::Feature2D {
 public:
  UprightOrbReference(int n, const FeatureOptions& o)
      : orb_(cv::ORB::create(n, 1.2f, o.orb_levels, 15, 0, 2, cv::ORB::FAST_SCORE, 31, o.orb_fast_threshold)) {}
  void detectAndCompute(cv::InputArray image, cv::InputArray mask, std::vector<cv::KeyPoint>& keypoints,
                        cv::OutputArray descriptors, bool /*use_provided*/) override {
    orb_->detect(image, keypoints, mask);
    std::stable_sort(keypoints.begin(), keypoints.end(), [](const cv::KeyPoint& p, const cv::KeyPoint& q) {
      return std::tie(p.octave, p.pt.y, p.pt.x) < std::tie(q.octave, q.pt.y, q.pt.x);
    });
    for (cv::KeyPoint& k : keypoints) k.angle = 0.f;
    orb_->compute(image, keypoints, descriptors);
  }

 private:
  cv::Ptr<cv::ORB> orb_;
};

cv::Ptr<cv::Feature2D> OrbReference(int n, const FeatureOptions& o) {
  if (o.orb_upright) return cv::makePtr<UprightOrbReference>(n, o);
  return cv::ORB::create(n, 1.2f, o.orb_levels, 15, 0, 2, cv::ORB::HARRIS_SCORE, 31, o.orb_fast_threshold);
}

TEST(FeatureTracker, DescriptorMatchesEqualOpenCvReferenceMatching) {
  const cv::Mat a = TexturedImage(), b = Zoomed(a);
  FeatureOptions o;
  o.sift_first_octave = -1;  // OpenCV's own SIFT (image doubled); the native first octave: below
  struct Case {
    Detector detector;
    bool orb_upright;
    cv::Ptr<cv::Feature2D> feature;
    int norm;
  };
  auto akaze = cv::AKAZE::create();
  akaze->setThreshold(o.akaze_threshold);
  FeatureOptions oriented = o;
  oriented.orb_upright = false;
  const Case cases[] = {
      {Detector::kSift, true, cv::SIFT::create(o.max_features, o.sift_octave_layers, o.sift_contrast_threshold),
       cv::NORM_L2},
      {Detector::kOrb, true, OrbReference(o.max_features, o), cv::NORM_HAMMING},                 // the default
      {Detector::kOrb, false, OrbReference(o.max_features, oriented), cv::NORM_HAMMING},  // OpenCV's ORB
      {Detector::kAkaze, true, akaze, cv::NORM_HAMMING},  // 61-byte descriptors: not a multiple of 8
  };
  for (const Case& c : cases) {
    o.detector = c.detector;
    o.orb_upright = c.orb_upright;
    const auto tracker = MakeFeatureTracker(o);
    std::vector<Match> matches;
    tracker->Track(a, b, &matches);
    std::vector<PointPair> got;
    for (const Match& m : matches) got.emplace_back(m.previous.x, m.previous.y, m.current.x, m.current.y);
    std::sort(got.begin(), got.end());
    const auto want = Reference(c.feature, c.norm, a, b, o);
    EXPECT_GE(want.size(), 20u) << DetectorName(c.detector) << " upright " << c.orb_upright;
    EXPECT_EQ(got, want) << DetectorName(c.detector) << " upright " << c.orb_upright;
    // The matches follow the zoom: current ≈ centre + 1.03 (previous − centre) within 1.5 px for most.
    std::size_t consistent = 0;
    for (const Match& m : matches) {
      const cv::Point2f predicted = cv::Point2f(128.f, 120.f) + 1.03f * (m.previous - cv::Point2f(128.f, 120.f));
      consistent += cv::norm(predicted - m.current) < 1.5 ? 1 : 0;
    }
    EXPECT_GE(consistent, matches.size() * 9 / 10) << DetectorName(c.detector) << " upright " << c.orb_upright;
  }
}

// ORB matching with descriptor counts that are not multiples of 8 (the vectorised distance loop's
// remainder) and different in the two frames: still the reference matches, upright and oriented.
TEST(FeatureTracker, OrbMatchesEqualReferenceForOddDescriptorCounts) {
  const cv::Mat a = TexturedImage(), b = Zoomed(a);
  for (bool upright : {true, false})
    for (int n : {203, 61, 13}) {
      FeatureOptions o;
      o.detector = Detector::kOrb;
      o.orb_upright = upright;
      o.max_features = n;
      const auto tracker = MakeFeatureTracker(o);
      std::vector<Match> matches;
      tracker->Track(a, b, &matches);
      std::vector<PointPair> got;
      for (const Match& m : matches) got.emplace_back(m.previous.x, m.previous.y, m.current.x, m.current.y);
      std::sort(got.begin(), got.end());
      const auto want = Reference(OrbReference(n, o), cv::NORM_HAMMING, a, b, o);
      EXPECT_GE(want.size(), 3u) << n << " upright " << upright;
      EXPECT_EQ(got, want) << n << " upright " << upright;
    }
}

// The upright ORB detector's keypoints are OpenCV's ORB's with FAST_SCORE (position, level, size,
// response; level by level, row by row) with angle 0, and its descriptors ORB::compute's of them,
// byte for byte: on textures, noise of odd size, a busy noisy texture, a checkerboard (many equal
// FAST scores: the ties at the cut), a flat image (none), images whose upper levels are too small for
// any keypoint and one too small for any, with several feature counts, level counts and FAST
// thresholds; and the same whichever image's cuts FAST starts from (from_last).
TEST(FeatureTracker, UprightOrbIsOrbFastScoreUnrotated) {
  std::vector<cv::Mat> images;
  images.push_back(TexturedImage());
  images.push_back(Zoomed(TexturedImage()));
  cv::RNG rng(5);
  cv::Mat noise(97, 131, CV_8U);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  images.push_back(noise);
  cv::Mat busy(192, 256, CV_8U), fine(192, 256, CV_8U), small(24, 32, CV_8U);
  rng.fill(small, cv::RNG::UNIFORM, 0, 256);
  cv::resize(small, busy, busy.size(), 0, 0, cv::INTER_CUBIC);
  rng.fill(fine, cv::RNG::UNIFORM, 0, 40);
  busy = busy * 0.8 + fine;
  images.push_back(busy);
  cv::Mat board(192, 256, CV_8U);
  for (int y = 0; y < board.rows; ++y)
    for (int x = 0; x < board.cols; ++x) board.at<unsigned char>(y, x) = ((x / 8 + y / 8) % 2) ? 200 : 40;
  images.push_back(board);
  images.push_back(cv::Mat(192, 256, CV_8U, cv::Scalar(77)));
  images.push_back(noise(cv::Rect(0, 0, 40, 36)).clone());  // level 1 is 33 × 30: too small
  images.push_back(noise(cv::Rect(5, 7, 30, 30)).clone());  // no level holds a keypoint
  std::size_t nonempty = 0;
  for (std::size_t k = 0; k < images.size(); ++k)
    for (const auto& [n, levels, threshold] :
         {std::tuple{400, 3, 20}, std::tuple{203, 4, 10}, std::tuple{13, 1, 30}, std::tuple{1000, 3, 5}}) {
      FeatureOptions o;
      o.max_features = n;
      o.orb_levels = levels;
      o.orb_fast_threshold = threshold;
      UprightOrbDetector detector(o);
      std::vector<cv::KeyPoint> got, want;
      cv::Mat got_desc, want_desc;
      detector.Detect(images[k], &got, &got_desc);
      UprightOrbReference(n, o).detectAndCompute(images[k], cv::noArray(), want, want_desc, false);
      const std::string where = "image " + std::to_string(k) + " n " + std::to_string(n);
      // Starting FAST from the cuts of each image (higher, lower, none, the same): the same result.
      for (std::size_t j = 0; j < images.size(); ++j) {
        std::vector<cv::KeyPoint> again;
        cv::Mat again_desc;
        detector.Detect(images[j], &again, &again_desc);
        detector.Detect(images[k], &again, &again_desc, true);
        ASSERT_EQ(again.size(), got.size()) << where << " after image " << j;
        for (std::size_t i = 0; i < got.size(); ++i) {
          EXPECT_EQ(again[i].pt, got[i].pt) << where << " after image " << j << " keypoint " << i;
          EXPECT_EQ(again[i].response, got[i].response) << where << " after image " << j << " keypoint " << i;
        }
        if (!got.empty()) {
          EXPECT_EQ(cv::norm(again_desc, got_desc, cv::NORM_L1), 0.0) << where << " after " << j;
        }
      }
      ASSERT_EQ(got.size(), want.size()) << where;
      for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].pt.x, want[i].pt.x) << where << " keypoint " << i;
        EXPECT_EQ(got[i].pt.y, want[i].pt.y) << where << " keypoint " << i;
        EXPECT_EQ(got[i].octave, want[i].octave) << where << " keypoint " << i;
        EXPECT_EQ(got[i].size, want[i].size) << where << " keypoint " << i;
        EXPECT_EQ(got[i].response, want[i].response) << where << " keypoint " << i;
        EXPECT_EQ(got[i].angle, 0.f) << where << " keypoint " << i;
      }
      if (got.empty()) {
        EXPECT_TRUE(got_desc.empty()) << where;
        continue;
      }
      ++nonempty;
      ASSERT_EQ(got_desc.rows, static_cast<int>(got.size())) << where;
      ASSERT_EQ(got_desc.cols, 32) << where;
      ASSERT_EQ(got_desc.type(), CV_8U) << where;
      ASSERT_EQ(want_desc.size(), got_desc.size()) << where;
      EXPECT_EQ(cv::norm(got_desc, want_desc, cv::NORM_L1), 0.0) << where;
    }
  EXPECT_GE(nonempty, 20u);  // the check is not vacuous
}

// SIFT with a native first octave runs OpenCV's SIFT on the half-size images: the same matches as the
// reference on those, mapped to full-size pixels (half-size pixel i covers 2i and 2i + 1), and they
// follow the zoom in full-size coordinates.
TEST(FeatureTracker, SiftNativeFirstOctaveIsSiftOnTheHalfImageMappedBack) {
  const cv::Mat a = TexturedImage(), b = Zoomed(a);
  FeatureOptions o;
  o.detector = Detector::kSift;
  o.sift_first_octave = 0;
  const auto tracker = MakeFeatureTracker(o);
  std::vector<Match> matches;
  tracker->Track(a, b, &matches);
  std::vector<PointPair> got;
  for (const Match& m : matches) got.emplace_back(m.previous.x, m.previous.y, m.current.x, m.current.y);
  std::sort(got.begin(), got.end());
  cv::Mat ha, hb;
  cv::resize(a, ha, cv::Size(128, 96), 0, 0, cv::INTER_AREA);
  cv::resize(b, hb, cv::Size(128, 96), 0, 0, cv::INTER_AREA);
  FeatureOptions half = o;
  half.max_displacement_px = o.max_displacement_px / 2.0;
  std::vector<PointPair> want;
  for (const auto& [pu, pv, cu, cv_] :
       Reference(cv::SIFT::create(o.max_features, o.sift_octave_layers, o.sift_contrast_threshold), cv::NORM_L2, ha, hb,
                 half))
    want.emplace_back(2.f * pu + 0.5f, 2.f * pv + 0.5f, 2.f * cu + 0.5f, 2.f * cv_ + 0.5f);
  std::sort(want.begin(), want.end());
  ASSERT_GE(want.size(), 20u);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_NEAR(std::get<0>(got[i]), std::get<0>(want[i]), 1e-4f);
    EXPECT_NEAR(std::get<1>(got[i]), std::get<1>(want[i]), 1e-4f);
    EXPECT_NEAR(std::get<2>(got[i]), std::get<2>(want[i]), 1e-4f);
    EXPECT_NEAR(std::get<3>(got[i]), std::get<3>(want[i]), 1e-4f);
  }
  std::vector<double> err;
  for (const Match& m : matches) {
    const cv::Point2f predicted = cv::Point2f(128.f, 120.f) + 1.03f * (m.previous - cv::Point2f(128.f, 120.f));
    err.push_back(cv::norm(predicted - m.current));
  }
  std::sort(err.begin(), err.end());
  EXPECT_LT(err[err.size() / 2], 0.5);
}

// The KLT tracker's Shi–Tomasi detector gives cv::goodFeaturesToTrack's corners in its order, on
// textures, a checkerboard (many equal values: the tie order), a flat image (none) and odd sizes.
TEST(FeatureTracker, ShiTomasiEqualsGoodFeaturesToTrack) {
  std::vector<cv::Mat> images;
  images.push_back(TexturedImage());
  images.push_back(Zoomed(TexturedImage()));
  cv::Mat noise(97, 131, CV_8U);
  cv::RNG rng(11);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  images.push_back(noise);
  cv::Mat board(192, 256, CV_8U);
  for (int y = 0; y < board.rows; ++y)
    for (int x = 0; x < board.cols; ++x) board.at<unsigned char>(y, x) = ((x / 8 + y / 8) % 2) ? 200 : 40;
  images.push_back(board);
  images.push_back(cv::Mat(192, 256, CV_8U, cv::Scalar(77)));
  ShiTomasiDetector detector;
  for (std::size_t k = 0; k < images.size(); ++k)
    for (const auto& [n, quality, spacing] : {std::tuple{400, 0.005, 5.0}, std::tuple{50, 0.05, 10.0},
                                              std::tuple{0, 0.01, 0.0}, std::tuple{1000, 0.001, 1.0}}) {
      std::vector<cv::Point2f> got, want;
      detector.Detect(images[k], n, quality, spacing, &got);
      cv::goodFeaturesToTrack(images[k], want, n, quality, spacing);
      ASSERT_EQ(got.size(), want.size()) << "image " << k << " n " << n;
      for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].x, want[i].x) << "image " << k << " corner " << i;
        EXPECT_EQ(got[i].y, want[i].y) << "image " << k << " corner " << i;
      }
    }
}

// KLT: corners tracked into the zoomed frame land where the zoom puts them (sub-pixel).
TEST(FeatureTracker, KltTracksTheZoom) {
  const cv::Mat a = TexturedImage(), b = Zoomed(a);
  FeatureOptions o;
  o.detector = Detector::kKlt;
  const auto tracker = MakeFeatureTracker(o);
  std::vector<Match> matches;
  tracker->Track(a, b, &matches);
  ASSERT_GE(matches.size(), 50u);
  std::vector<double> err;
  for (const Match& m : matches) {
    const cv::Point2f predicted = cv::Point2f(128.f, 120.f) + 1.03f * (m.previous - cv::Point2f(128.f, 120.f));
    err.push_back(cv::norm(predicted - m.current));
  }
  std::sort(err.begin(), err.end());
  EXPECT_LT(err[err.size() / 2], 0.1);
}

}  // namespace
}  // namespace squint::obstacles
