// libFuzzer entry point: any bytes as a mesh file of the format the first byte picks ('o' OBJ,
// 'p' PLY, 's' STL, 'g' glTF, 'b' binary glTF; other bytes by value), read through Assimp as a scene's
// mesh is (scene/mesh.h), with a 3 s limit. A mesh is either refused with an InputError (one printable line) or read
// into finite vertices and valid triangles.
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/errors.h"
#include "fuzz_check.h"
#include "scene/mesh.h"

namespace {

// A folder of this process's own for the file under test (the loader reads files by path).
const std::filesystem::path& work_folder() {
    static const std::filesystem::path folder = [] {
        auto f = std::filesystem::temp_directory_path() / ("sdfbrick-fuzz-mesh-" + std::to_string(::getpid()));
        std::filesystem::create_directories(f);
        return f;
    }();
    return folder;
}

const char* extension(std::uint8_t selector) {
    switch (selector) {
        case 'o': return ".obj";
        case 'p': return ".ply";
        case 's': return ".stl";
        case 'g': return ".gltf";
        case 'b': return ".glb";
        default: {
            static constexpr std::array<const char*, 5> any = {".obj", ".ply", ".stl", ".gltf", ".glb"};
            return any[selector % any.size()];
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace sdfbrick;
    if (size == 0) return 0;
    const std::filesystem::path path = work_folder() / (std::string("mesh") + extension(data[0]));
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
    }
    try {
        const TriangleMesh mesh = load_mesh(path, 3);  // a reader that hangs is refused after 3 s
        for (const auto& v : mesh.vertices)
            if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) std::abort();
        for (const auto& t : mesh.triangles)
            for (const std::uint32_t i : t)
                if (i >= mesh.vertices.size()) std::abort();
        (void)topology(mesh);
    } catch (const InputError& e) {
        fuzz::check_refusal(e.what());
    }
    std::filesystem::remove(path);
    return 0;
}
