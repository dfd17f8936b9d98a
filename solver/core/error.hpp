#pragma once
// One exception type for every user-facing failure. The message must name the
// file/key/block/cell concerned and what was expected, so it can be printed as is.
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace narwhal {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

template <class... Args>
[[noreturn]] void fail(fmt::format_string<Args...> f, Args&&... args) {
  throw Error(fmt::format(f, std::forward<Args>(args)...));
}

}  // namespace narwhal
