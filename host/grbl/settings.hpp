// settings.hpp — grbl's `$$` settings, pure: the machine config's values under grbl's numbers
// (rates in mm/min, travel as a length), so a sender shows the machine it drives. They are
// the config's, read-only over the port: `$N=value` with the value the setting already has is
// accepted (senders write settings back), any other value is refused with error:5 (setting
// disabled), an unknown number with error:3, a value that is not a number with error:2.
// docs/grbl-protocol.md lists the table.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "config/config.hpp"

namespace pcnc::grbl {

struct Setting {
  int number = 0;
  double value = 0.0;
  int decimals = 3;  // as grbl prints it: 0 for integers and masks
};

/// The settings a sender reads with `$$`, in grbl's order.
std::vector<Setting> settings_for(const MachineConfig& config);

/// "$110=6000.000"
std::string format_setting(const Setting& s);

/// The answer to a `$N=value` line (without the '$'): 0 (ok, the value is the setting's
/// own) or the grbl error number.
int write_setting(const std::vector<Setting>& settings, std::string_view assignment);

}  // namespace pcnc::grbl
