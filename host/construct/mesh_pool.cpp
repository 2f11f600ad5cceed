#include "construct/mesh_pool.h"

#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "construct/mesh_grid.h"
#include "core/errors.h"
#include "scene/mesh.h"

namespace sdfbrick::construct {

namespace {

constexpr std::size_t kHeaderFloats = sizeof(SdfMeshGrid) / sizeof(float);

// The grid values of source, converted on the device on first use.
const std::vector<float>& grid_values(MeshSource& source, std::optional<MeshGridBuilder>& builder, ocl::Device& device,
                                      measure::Scheduler& scheduler) {
    std::lock_guard lock(source.mutex);
    if (source.values.empty()) {
        if (!builder) builder.emplace(device);
        source.values = source.sparse ? builder->build_sparse(source.mesh, source.frame, source.band, scheduler).values
                                      : builder->build(source.mesh, source.frame, scheduler).values;
    }
    if (!source.sparse && source.values.size() != source.frame.points())
        throw std::logic_error(fmt::format("mesh_pool: the grid of {} holds {} values for {} points", source.file,
                                           source.values.size(), source.frame.points()));
    return source.values;
}

SdfMeshGrid header(const MeshSource& s, std::size_t offset) {
    const GridFrame& f = s.frame;
    SdfMeshGrid h{};
    for (int a = 0; a < 3; ++a) {
        h.origin[a] = static_cast<float>(f.origin[a]);
        h.dims[a] = static_cast<sdf_u32>(f.dims[a]);
    }
    h.cell = static_cast<float>(f.cell);
    h.inv_cell = static_cast<float>(1.0 / f.cell);
    h.offset = static_cast<sdf_u32>(offset);
    if (s.sparse) {
        const glm::ivec3 t = sparse_tiles(f);
        h.tiles = static_cast<sdf_u32>(offset);
        const std::size_t table = static_cast<std::size_t>(t.x) * t.y * t.z;
        h.coarse = static_cast<sdf_u32>(offset + table);
        h.centres = static_cast<sdf_u32>(offset + table + static_cast<std::size_t>(t.x + 1) * (t.y + 1) * (t.z + 1));
    }
    return h;
}

}  // namespace

std::vector<float> mesh_pool(std::span<const Geometry> geometries, ocl::Device& device, measure::Scheduler& scheduler) {
    std::vector<MeshSource*> slots;  // by mesh index
    for (const Geometry& g : geometries)
        for (const Edit& e : g.edits) {
            if (e.primitive != Primitive::Mesh) continue;
            const auto index = static_cast<std::size_t>(e.params[3]);
            if (slots.size() <= index) slots.resize(index + 1, nullptr);
            slots[index] = e.mesh.get();
        }
    if (slots.empty()) return {0.0f};
    std::optional<MeshGridBuilder> builder;
    std::size_t total = slots.size() * kHeaderFloats;
    for (MeshSource* s : slots) total += s ? grid_values(*s, builder, device, scheduler).size() : 0;
    if (total > std::numeric_limits<sdf_u32>::max() || total * sizeof(float) > device.info().max_alloc_bytes)
        throw InputError(fmt::format("the scene's mesh grids need {} bytes; {} allocates at most {} bytes at once",
                                     total * sizeof(float), device.info().name, device.info().max_alloc_bytes));
    std::vector<float> pool(slots.size() * kHeaderFloats, 0.0f);
    pool.reserve(total);
    for (std::size_t i = 0; i < slots.size(); ++i) {
        if (!slots[i]) continue;
        const std::size_t base = pool.size();
        const SdfMeshGrid h = header(*slots[i], base);
        std::memcpy(pool.data() + i * kHeaderFloats, &h, sizeof h);
        pool.insert(pool.end(), slots[i]->values.begin(), slots[i]->values.end());
        if (!slots[i]->sparse) continue;
        for (std::size_t e = h.tiles; e < h.coarse; ++e) {  // the tile table: offsets within the grid -> within the pool
            sdf_u32 entry = 0;
            std::memcpy(&entry, &pool[e], sizeof entry);
            if (entry != SDF_MESH_NO_TILE) entry += static_cast<sdf_u32>(base);
            std::memcpy(&pool[e], &entry, sizeof entry);
        }
    }
    return pool;
}

}  // namespace sdfbrick::construct
