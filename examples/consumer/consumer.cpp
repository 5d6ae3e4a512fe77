// 256 sensors of HydroShear at the default parameters, a 4 mm sphere pressed 1 mm into each (env e at
// x = e * 10 um) and slid 0.5 mm along x_E; prints the centre marker's displacement of env 0 and exits 1
// unless the press gave a field (the check CI runs against the installed package).
#include <cmath>
#include <cstdio>
#include <shearbench/sensor_model.hpp>
#include <vector>

int main() {
  try {
    shearbench::Config config;
    config.model = "hydroshear";
    config.indenter = R"({"shape": "sphere", "radius_m": 0.004})";
    config.envs = 256;
    shearbench::SensorModel model = shearbench::SensorModel::create(config);
    const int E = model.envs(), M = model.markers();
    std::vector<double> X_EI(E * shearbench::kPoseValues), field(E * M * 2);
    for (int k = 0; k <= 20; ++k) {
      const double depth = 1e-3 * std::min(1.0, k / 10.0), slide = 0.5e-3 * std::max(0.0, (k - 10) / 10.0);
      for (int e = 0; e < E; ++e) {
        const double pose[7] = {e * 1e-5 + slide, 0, 0.004 - depth, 1, 0, 0, 0};
        std::copy(pose, pose + 7, X_EI.begin() + e * 7);
      }
      model.step(X_EI, 1.0 / 60, field);
    }
    const int centre = 3 * 9 + 4;  // row 3, column 4 of the 9 x 7 grid
    std::printf("consumer: shearbench %s, %s on %d envs x %d markers: centre marker of env 0 (%.3f, %.3f) px\n",
                shearbench::version().c_str(), model.model().c_str(), E, M, field[2 * centre], field[2 * centre + 1]);
    return std::hypot(field[2 * centre], field[2 * centre + 1]) > 0.1 ? 0 : 1;
  } catch (const shearbench::Error& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 2;
  }
}
