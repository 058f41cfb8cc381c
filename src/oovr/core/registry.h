// Registry of named implementations (scenes now; schemes and policies later).
// An implementation registers itself with one line in its own .cpp:
//
//   static const Registry<SceneFactory>::Add reg("courtyard", {...});
//
// The library is linked whole-archive so such files cannot be dropped by the
// linker; a test lists every registered name so a missing one is noticed.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "oovr/core/error.h"

namespace oovr {

template <class T>
class Registry {
 public:
  struct Add {
    Add(const std::string& name, T entry) {
      auto& m = entries();
      if (!m.emplace(name, std::move(entry)).second) throw Error("duplicate registration: " + name);
    }
  };

  static const T* find(const std::string& name) {
    const auto& m = entries();
    const auto it = m.find(name);
    return it == m.end() ? nullptr : &it->second;
  }

  static std::vector<std::string> names() {
    std::vector<std::string> n;
    for (const auto& [k, v] : entries()) n.push_back(k);
    return n;
  }

 private:
  static std::map<std::string, T>& entries() {
    static std::map<std::string, T> m;
    return m;
  }
};

}  // namespace oovr
