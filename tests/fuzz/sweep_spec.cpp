// libFuzzer entry point: any bytes as a sweep file (sweep/grid.h). A spec is either refused with an
// InputError (one printable line) or read, validated and expanded over two devices within the point
// limit; a read spec writes to JSON and reads back to the same JSON.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "core/errors.h"
#include "fuzz_check.h"
#include "scene/scene_json.h"
#include "sweep/grid.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace sdfbrick;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const sweep::SweepSpec spec = sweep::spec_from_json(parse_json_text(text, "fuzz.json"), "fuzz.json");
        spec.validate();
        const nlohmann::json written = sweep::to_json(spec);
        if (sweep::to_json(sweep::spec_from_json(written, "written.json")) != written) std::abort();  // round trip
        const auto points = sweep::expand(spec, {"device A", "device B"}, 4096);
        for (const auto& p : points) (void)p.key(spec);
        (void)sweep::shard_points(points, sweep::Shard{1, 3});
    } catch (const InputError& e) {
        fuzz::check_refusal(e.what());
    }
    return 0;
}
