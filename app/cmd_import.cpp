// shearbench import: converts one raw recording folder (<data>/raw/...) into tsd/1.
#include <cstdio>

#include "app/command.hpp"
#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/data/importers.hpp"

namespace sb::app {
namespace {

struct ImportArgs {
  bool frames = false;
  std::string source, in, out, grid = "auto", sensor;
  double mm_per_px = 0.0634;
  int max_samples = 0;
  bool no_pin_prior = false, no_lattice_check = false;
};

// Fewer calibration samples than the pin prior needs: no prior is fitted and every deep press loses all
// its pins, so the import would write samples with nothing tracked. Refused before any work.
void require_enough_for_pin_prior(const ImportArgs& a) {
  const int need = tactip_prior_min_calibration_samples();
  if (a.no_pin_prior || a.max_samples == 0 || a.max_samples >= need) return;
  throw InputError("--max-samples",
                   std::to_string(a.max_samples) + " calibration samples are too few for the pin prior (it needs " +
                       std::to_string(need) + "; with fewer, deep presses keep 0 pins): use --max-samples " +
                       std::to_string(need) + " or more, 0 for all, or --no-pin-prior");
}

int run_import(const ImportArgs& args, const GlobalOptions& g) {
  ImportArgs a = args;
  // "data:raw/tactip_shear", as every other command names a folder of the data root.
  if (a.in.rfind("data:", 0) == 0) a.in = resolve_path(a.in, resolve_data_root(g.data_root_flag), "");
  TrackerOptions opts;
  parse_grid(a.grid, "--grid", opts);
  ImportReport report;
  if (a.source == "gsrobotics")
    report = import_gsrobotics(a.in, a.out, opts, a.mm_per_px, a.frames);
  else if (a.source == "incipient_slip")
    report = import_incipient_slip(a.in, a.out, opts, a.mm_per_px, a.frames);
  else if (a.source == "fots")
    report = import_fots(a.in, a.out);
  else if (a.source == "feats")
    report = import_feats(a.in, a.out);
  else if (a.source == "tactip_shear") {
    require_enough_for_pin_prior(a);
    TactipImportOptions t;
    t.max_samples_per_split = a.max_samples;
    t.use_prior = !a.no_pin_prior;
    t.lattice_check = !a.no_lattice_check;
    t.frames = a.frames;
    t.sensor_file = a.sensor;
    report = import_tactip_shear(a.in, a.out, t);
  } else
    throw InputError("--source",
                     "unknown source '" + a.source + "' (gsrobotics, incipient_slip, fots, feats, tactip_shear)");
  for (const auto& l : report.lines) std::printf("%s\n", l.c_str());
  for (const auto& d : report.datasets) std::printf("wrote %s\n", d.c_str());
  return 0;
}

void add_flags(CLI::App& sub, ImportArgs& a) {
  sub.add_option("--source", a.source, "gsrobotics | incipient_slip | fots | feats | tactip_shear")->required();
  sub.add_option("--in", a.in, "raw folder (e.g. data:raw/gsrobotics_tracking, in the data root)")->required();
  sub.add_option("--out", a.out, "output directory (video sources: one dataset per recording inside)")->required();
  sub.add_option("--grid", a.grid, "marker grid for video sources (ROWSxCOLS or auto)")->capture_default_str();
  sub.add_option("--mm-per-px", a.mm_per_px, "scale for video sources")->capture_default_str();
  sub.add_option("--max-samples", a.max_samples,
                 "tactip_shear: only the first N samples of each split (0 = all; the pin prior is fitted on the "
                 "calibration samples imported and needs 66: fewer is refused unless --no-pin-prior)")
      ->check(CLI::NonNegativeNumber);
  sub.add_flag("--no-pin-prior", a.no_pin_prior,
               "tactip_shear: track every image without the prior predicted from its targets (the old tracker)");
  sub.add_flag("--no-lattice-check", a.no_lattice_check,
               "tactip_shear: keep the pins the lattice-slip check doubts (they are dropped by default)");
  sub.add_option("--sensor", a.sensor,
                 "tactip_shear: a sensor description (JSON; docs/sensors.md): its values are taken as given "
                 "instead of identified or defaulted (e.g. dome_radius_mm, pin_depth_mm, focal_px)");
  sub.add_flag(
      "--frames", a.frames,
      "video sources and tactip_shear: also store the frames as PNG (the workbench shows them behind the panels)");
}

const Subcommand<ImportArgs> kImportCommand{
    "import", "convert a raw recording folder (gsrobotics, incipient_slip, fots, feats, tactip_shear) into tsd/1", 41,
    add_flags, run_import};

}  // namespace
}  // namespace sb::app
