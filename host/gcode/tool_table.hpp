// tool_table.hpp — PROVISIONAL (replaced by the wt-state branch).
#pragma once

#include <string>
#include <vector>

#include "geometry/vec3.hpp"

namespace pcnc {

struct ToolEntry {
  int number = 0;
  int pocket = 0;
  Vec3 offset{};
  double diameter = 0;
  std::string comment;
  int line = 0;
};

class ToolTable {
 public:
  const ToolEntry* find(int number) const {
    for (const ToolEntry& t : tools_)
      if (t.number == number) return &t;
    return nullptr;
  }
  void set(const ToolEntry& e) {
    for (ToolEntry& t : tools_)
      if (t.number == e.number) { t = e; return; }
    tools_.push_back(e);
  }
  const std::vector<ToolEntry>& tools() const { return tools_; }

 private:
  std::vector<ToolEntry> tools_;
};

}  // namespace pcnc
