// measure.hpp — `pcnc measure`: on-machine measurement after the seed paper (issue 15 item 3,
// docs/measurement.md). Drives a served machine (`pcnc serve`) through its control socket by
// running generated probing programs (measure_program.hpp) that log every touch:
//   1. the volumetric error, calibrated on the reference artefact (the config's ball plate:
//      each ball's centre fitted from 9 touches, the known distances between them);
//   2. the probe's effective radius by approach direction (the seed's Fig. 2) on the
//      reference sphere, with its known centre, the touches corrected by step 1's model;
//   3. the workpiece: a grid (or a list of X/Y points) probed along the estimate's normal;
//      the latched centres corrected for the volumetric error, then moved back by the
//      calibrated effective radius along the normal of the measured data;
// and writes the compensated points as the grid CSV `pcnc surface fit` reads. Steps 1-2 are
// written to a calibration file that --calibration reads back instead of calibrating again.
#pragma once

namespace CLI {
class App;
}

namespace pcnc {

/// Registers `measure`; the callback stores the exit status (config/exit_status.hpp).
void add_measure_subcommand(CLI::App& app, int& exit_code);

}  // namespace pcnc
