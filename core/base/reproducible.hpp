#pragma once
// Wall-clock times are the only thing that makes two runs of the same command on the same machine
// write different files. `shearbench --reproducible` (or SHEARBENCH_REPRODUCIBLE=1) leaves them out of
// every output (JSON and markdown), so fits, evaluations and reports are bit-identical run to run.
namespace sb {

bool timings_in_outputs();
void set_timings_in_outputs(bool on);

}  // namespace sb
