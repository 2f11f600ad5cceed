// Error types shared by the whole library. The CLI maps them to exit codes:
//   InputError  -> exit 2 (the user's input is wrong: scene file, option value, device name, ...)
//   SettingError (an InputError) -> exit 2, the line naming the flag that set the setting
//   VerdictFailure -> exit 3 (the input is sound and was judged: it fails, as compare --gate's regression)
//   any other std::exception (ClError, ...) -> exit 1
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace sdfbrick {

// Bad input. The message is one line that names the place: "FILE: /json/path: what is wrong".
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A bad value of one setting. setting() is the library's own name for it (BuildSettings::chunk ->
// "chunk", TraceSettings::group_x -> "group_x"); the message is one line in library terms
// ("chunk must lie in 16..256, got 8"). Whoever set the value (the CLI's flag, a sweep file's key)
// names itself in front of the message. A message that advises several settings names them all and
// carries the first.
class SettingError : public InputError {
public:
    SettingError(std::string setting, const std::string& message) : InputError(message), setting_(std::move(setting)) {}
    const std::string& setting() const { return setting_; }

private:
    std::string setting_;
};

// A command that judges its input found it failing (compare --gate: the new report regressed). Not
// an error: the command ran to the end and wrote its outputs. The message is one line saying why.
class VerdictFailure : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace sdfbrick
