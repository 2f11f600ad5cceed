// Error types shared by the whole library. The CLI maps them to exit codes:
//   InputError  -> exit 2 (the user's input is wrong: scene file, option value, device name, ...)
//   any other std::exception (ClError, ...) -> exit 1
#pragma once

#include <stdexcept>
#include <string>

namespace sdfbrick {

// Bad input. The message is one line that names the place: "FILE: /json/path: what is wrong".
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace sdfbrick
