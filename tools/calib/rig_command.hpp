// `tumble-calib rig RECORDING_DIR [options]` as a function of its command
// line (argv[0] is "rig"), so main.cpp only dispatches to it.
// Exit: 0 calibrated; 1 the recording cannot give the calibration (too
// little rotation, too few registered scans, offset out of range); 2 bad
// command line or a missing or unreadable file.
#pragma once

namespace tumble::calib {

int run_rig_command(int argc, char** argv);

}  // namespace tumble::calib
