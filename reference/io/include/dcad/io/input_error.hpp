// Bad input: the one error the readers throw (the CLI's exit 1).  The message names the file, the
// line or JSON path, what was expected and what was found.
#pragma once

#include <stdexcept>

namespace dcad::io {

struct InputError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

}  // namespace dcad::io
