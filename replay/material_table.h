// A scene's named materials ("materials"): their names in document order,
// for messages, and an index by name, so that n bodies naming materials of
// a table of m cost O(n log m), not the O(n m) of a scan per body.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/body.h"

namespace bitstep {

class MaterialTable {
 public:
  // False (and nothing added) when the name is taken.
  bool add(const std::string& name, const Material& material) {
    if (!by_name_.emplace(name, material).second) return false;
    names_.push_back(name);
    return true;
  }
  const Material* find(std::string_view name) const {
    const auto found = by_name_.find(name);
    return found == by_name_.end() ? nullptr : &found->second;
  }
  const std::vector<std::string>& names() const { return names_; }  // document order

 private:
  std::vector<std::string> names_;
  std::map<std::string, Material, std::less<>> by_name_;
};

}  // namespace bitstep
