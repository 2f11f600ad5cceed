// libFuzzer entry point: any bytes as an edit log (scene/edit_log.h) against a scene of two
// geometries. A log is either refused with an InputError (one printable line) or read, and then
// every operation applies in order without failing, as parsing promised.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "core/errors.h"
#include "fuzz_check.h"
#include "scene/edit_log.h"
#include "scene/scene_json.h"

namespace {

const sdfbrick::Scene& scene() {
    static const sdfbrick::Scene s = sdfbrick::parse_scene(
        R"({"geometries": [
              {"name": "clay", "edits": [{"primitive": "sphere", "radius": 1}, {"primitive": "box", "half_extents": [1, 0.2, 1], "blend": 0.1}]},
              {"name": "stand", "edits": [{"primitive": "cylinder", "half_height": 0.5, "radius": 0.3}]}]})",
        "fuzz-scene.json");
    return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace sdfbrick;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const EditLog log = parse_edit_log(text, "fuzz.jsonl", scene());
        Scene s = scene();
        for (const EditOp& op : log.ops) apply(s, op);
        for (const Geometry& g : s.geometries)
            if (g.edits.empty()) std::abort();  // a log never empties a geometry
    } catch (const InputError& e) {
        fuzz::check_refusal(e.what());
    }
    return 0;
}
