// pcnc_main.cpp — the entry of the `pcnc` executable: its command line is command_line.cpp.
#include "command_line.hpp"

int main(int argc, char** argv) { return pcnc::run_command_line(argc, argv); }
