// libFuzzer entry point: any bytes as a scene file. A scene is either refused with an InputError
// (one line, printable) or read; a read scene writes and reads back to the same scene. Anything
// else (another exception, a crash, a sanitizer report, a message of several lines) is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "core/errors.h"
#include "fuzz_check.h"
#include "scene/scene_info.h"
#include "scene/scene_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace sdfbrick;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    Scene scene;
    try {
        scene = parse_scene(text, "fuzz.json");
    } catch (const InputError& e) {
        fuzz::check_refusal(e.what());
        return 0;
    }
    const std::string written = format_scene(scene);
    if (format_scene(parse_scene(written, "written.json")) != written) std::abort();  // round trip
    (void)to_text(scene_summary(scene));
    return 0;
}
