// Compares a rendered PNG against its baseline with one metric: the mean SSIM (Wang et al. 2004:
// 11x11 Gaussian window, sigma 1.5, K1 = 0.01, K2 = 0.03) of the greyscale images. Usage:
//   image_compare BASELINE ACTUAL DIFF_OUT MIN_SSIM
// Exit 0 when SSIM >= MIN_SSIM. On failure writes DIFF_OUT (absolute difference, amplified). A missing
// baseline is written from ACTUAL and the comparison fails until it is committed.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace {

double mean_ssim(const cv::Mat& a8, const cv::Mat& b8) {
  constexpr double kC1 = (0.01 * 255) * (0.01 * 255);
  constexpr double kC2 = (0.03 * 255) * (0.03 * 255);
  const cv::Size window(11, 11);
  constexpr double kSigma = 1.5;
  cv::Mat a, b;
  a8.convertTo(a, CV_64F);
  b8.convertTo(b, CV_64F);
  cv::Mat mu_a, mu_b, saa, sbb, sab;
  cv::GaussianBlur(a, mu_a, window, kSigma);
  cv::GaussianBlur(b, mu_b, window, kSigma);
  cv::GaussianBlur(a.mul(a), saa, window, kSigma);
  cv::GaussianBlur(b.mul(b), sbb, window, kSigma);
  cv::GaussianBlur(a.mul(b), sab, window, kSigma);
  const cv::Mat mu_aa = mu_a.mul(mu_a), mu_bb = mu_b.mul(mu_b), mu_ab = mu_a.mul(mu_b);
  saa -= mu_aa;
  sbb -= mu_bb;
  sab -= mu_ab;
  const cv::Mat num = (2 * mu_ab + kC1).mul(2 * sab + kC2);
  const cv::Mat den = (mu_aa + mu_bb + kC1).mul(saa + sbb + kC2);
  cv::Mat ssim;
  cv::divide(num, den, ssim);
  return cv::mean(ssim)[0];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: image_compare BASELINE ACTUAL DIFF_OUT MIN_SSIM\n");
    return 2;
  }
  const std::string baseline = argv[1], actual = argv[2], diff_out = argv[3];
  const double min_ssim = std::atof(argv[4]);
  const cv::Mat act = cv::imread(actual, cv::IMREAD_COLOR);
  if (act.empty()) {
    std::fprintf(stderr, "image_compare: cannot read the rendered image %s\n", actual.c_str());
    return 1;
  }
  if (!std::filesystem::exists(baseline)) {
    std::filesystem::create_directories(std::filesystem::path(baseline).parent_path());
    std::filesystem::copy_file(actual, baseline);
    std::fprintf(stderr, "image_compare: no baseline; wrote %s from this render. Look at it, commit it, rerun.\n",
                 baseline.c_str());
    return 1;
  }
  const cv::Mat base = cv::imread(baseline, cv::IMREAD_COLOR);
  if (base.size() != act.size()) {
    std::fprintf(stderr, "image_compare: size %dx%d differs from the baseline's %dx%d\n", act.cols, act.rows, base.cols,
                 base.rows);
    return 1;
  }
  cv::Mat ga, gb;
  cv::cvtColor(base, gb, cv::COLOR_BGR2GRAY);
  cv::cvtColor(act, ga, cv::COLOR_BGR2GRAY);
  const double ssim = mean_ssim(gb, ga);
  std::printf("SSIM %.5f (threshold %.3f) %s vs %s\n", ssim, min_ssim, actual.c_str(), baseline.c_str());
  if (ssim >= min_ssim) return 0;
  cv::Mat diff;
  cv::absdiff(base, act, diff);
  diff *= 4;  // small differences made visible
  cv::imwrite(diff_out, diff);
  std::fprintf(stderr, "image_compare: FAILED: SSIM %.5f < %.3f; actual %s, diff %s\n", ssim, min_ssim, actual.c_str(),
               diff_out.c_str());
  return 1;
}
