#include "scene/scene_json.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "core/quote.h"
#include "scene/json_node.h"
#include "scene/level_set.h"
#include "scene/mesh.h"

namespace sdfbrick {

using nlohmann::json;

namespace {

using detail::Node;

// How much of a file name a message echoes.
constexpr std::size_t kPathEchoLimit = 256;

void read_transform_fields(const Node& n, Transform& t) {
    if (n.has("position")) t.translation = n["position"].vec3();
    if (n.has("rotation")) t.rotation = n["rotation"].quaternion();
    if (n.has("scale")) t.scale = n["scale"].positive();
}

Animation read_animation(const Node& n) {
    n.expect_object({"velocity", "acceleration", "spin_axis", "spin_rate", "wrap_y"});
    Animation a;
    if (n.has("velocity")) a.velocity = n["velocity"].vec3();
    if (n.has("acceleration")) a.acceleration = n["acceleration"].vec3();
    if (n.has("spin_axis")) a.spin_axis = n["spin_axis"].nonzero_vec3();
    if (n.has("spin_rate")) a.spin_rate = n["spin_rate"].number();
    if (n.has("wrap_y")) {
        const Node w = n["wrap_y"];
        const auto r = w.numbers<2>();
        if (!(r[1] > r[0])) w.fail(fmt::format("needs [low, high] with high > low, got [{}, {}]", r[0], r[1]));
        a.wrap_y = r;
    }
    return a;
}

Primitive read_primitive(const Node& n) {
    const Node prim_node = n["primitive"];
    const std::string prim_name = prim_node.string();
    const auto prim = primitive_from_string(prim_name);
    if (!prim) {
        std::string names;
        for (std::size_t i = 0; i < kPrimitiveCount; ++i)
            names += (i ? ", " : "") + std::string(to_string(static_cast<Primitive>(i)));
        names += ", vdb";
        prim_node.fail(fmt::format("unknown primitive {} (known: {})", quoted_input(prim_name), names));
    }
    return *prim;
}

// The fields every edit may have.
constexpr std::array<std::string_view, 7> kCommonEditFields = {"primitive", "position", "rotation", "scale",
                                                               "op", "blend", "animation"};

// The primitive's own fields (and no unknown key): its parameters, as kernels/sdf_types.h orders them.
std::array<double, 4> read_params(const Node& n, Primitive prim) {
    auto allow = [&](std::initializer_list<std::string_view> own) {
        std::vector<std::string_view> all(kCommonEditFields.begin(), kCommonEditFields.end());
        all.insert(all.end(), own);
        n.expect_keys(all, "a " + std::string(to_string(prim)));
    };
    std::array<double, 4> p{};
    switch (prim) {
        case Primitive::Sphere:
            allow({"radius"});
            p[0] = n["radius"].positive();
            break;
        case Primitive::Box: {
            allow({"half_extents"});
            const glm::dvec3 b = n["half_extents"].positive_vec3();
            p = {b.x, b.y, b.z, 0.0};
            break;
        }
        case Primitive::RoundBox: {
            allow({"half_extents", "rounding"});
            const glm::dvec3 b = n["half_extents"].positive_vec3();
            const Node r = n["rounding"];
            p = {b.x, b.y, b.z, r.non_negative()};
            if (p[3] > std::min({b.x, b.y, b.z}))
                r.fail(fmt::format("must not exceed the smallest half extent ({}), got {}", std::min({b.x, b.y, b.z}), p[3]));
            break;
        }
        case Primitive::Torus:
            allow({"major_radius", "minor_radius"});
            p[0] = n["major_radius"].positive();
            p[1] = n["minor_radius"].positive();
            break;
        case Primitive::Capsule:
            allow({"half_length", "radius"});
            p[0] = n["half_length"].non_negative();
            p[1] = n["radius"].positive();
            break;
        case Primitive::Cylinder:
            allow({"half_height", "radius"});
            p[0] = n["half_height"].positive();
            p[1] = n["radius"].positive();
            break;
        case Primitive::Cone:
            allow({"half_height", "radius_bottom", "radius_top"});
            p[0] = n["half_height"].positive();
            p[1] = n["radius_bottom"].non_negative();
            p[2] = n["radius_top"].non_negative();
            if (p[1] == 0.0 && p[2] == 0.0) n["radius_top"].fail("radius_bottom and radius_top must not both be 0");
            break;
        case Primitive::Ellipsoid: {
            allow({"radii"});
            const glm::dvec3 r = n["radii"].positive_vec3();
            p = {r.x, r.y, r.z, 0.0};
            break;
        }
        case Primitive::Menger:
            allow({"half_size", "iterations"});
            p[0] = n["half_size"].positive();
            p[1] = n.has("iterations") ? n["iterations"].integer(1, 6) : 3;
            break;
        case Primitive::Mesh: throw std::logic_error("read_params: mesh edits are read by read_mesh_edit");
    }
    return p;
}

// The scene's meshes: one MeshSource per file and resolution, numbered in order of first use.
struct MeshCatalog {
    std::filesystem::path base;  // mesh files are relative to the scene file's folder
    struct Entry {
        std::shared_ptr<MeshSource> source;
        std::uint32_t index = 0;
    };
    std::map<std::tuple<std::string, int, bool>, Entry> entries;  // file (and grid), resolution, sparse
    std::vector<std::string> warnings;  // one line per mesh whose winding was turned
};

std::mutex allowed_folders_mutex;
std::vector<std::filesystem::path> allowed_folders;

// Whether a mesh file may be read: it lies (links resolved) in the scene's folder or in a folder
// allowed outside it.
bool mesh_file_allowed(const std::filesystem::path& path, const std::filesystem::path& base) {
    if (lies_within(path, base.empty() ? std::filesystem::path(".") : base)) return true;
    const std::scoped_lock lock(allowed_folders_mutex);
    return std::any_of(allowed_folders.begin(), allowed_folders.end(),
                       [&](const std::filesystem::path& f) { return lies_within(path, f); });
}

// Refuses a file outside the scene's folder and the folders allowed outside it.
void check_file_allowed(const Node& file, const std::filesystem::path& path, const std::filesystem::path& base) {
    if (!mesh_file_allowed(path, base))
        file.fail(fmt::format("{}: refused: outside the scene's folder{} and the folders allowed outside it",
                              escaped(path.string(), kPathEchoLimit),
                              base.empty() ? "" : " " + escaped(base.string(), kPathEchoLimit)));
}

// The mesh a mesh edit's "file" names. Every refusal names the place in the scene, then the file
// (load_mesh and make_mesh_source name it first in their messages).
std::shared_ptr<MeshSource> read_mesh_source(const Node& file, const std::filesystem::path& path, int resolution,
                                             bool sparse) {
    const auto named = [&](auto&& step) {
        try {
            return step();
        } catch (const InputError& e) {
            file.fail(escaped(e.what(), 2 * kPathEchoLimit));
        }
    };
    TriangleMesh mesh = named([&] { return load_mesh(path); });
    const Aabb b = mesh.bounds();
    const glm::dvec3 m = glm::max(glm::abs(b.lo), glm::abs(b.hi));
    const double reach = std::max({m.x, m.y, m.z});
    if (reach > kSceneNumberLimit)
        file.fail(fmt::format("{}: a vertex coordinate of magnitude {} is out of range: scene numbers lie in [-{:g}, {:g}]",
                              escaped(path.string(), kPathEchoLimit), reach, kSceneNumberLimit, kSceneNumberLimit));
    auto source = named([&] { return make_mesh_source(std::move(mesh), path.string(), resolution, sparse); });
    source->file = file.string();
    return source;
}

// A mesh edit's own fields: the file, the grid's resolution (cells along the longest side) and kind.
Edit read_mesh_edit(const Node& n, MeshCatalog& catalog) {
    std::vector<std::string_view> allowed(kCommonEditFields.begin(), kCommonEditFields.end());
    allowed.insert(allowed.end(), {"file", "resolution", "grid"});
    n.expect_keys(allowed, "a mesh");
    const Node file = n["file"];
    const std::string name = file.string();
    if (name.empty()) file.fail("must not be empty");
    bool sparse = true;
    if (n.has("grid")) {
        const std::string kind = n["grid"].string();
        if (kind != "sparse" && kind != "dense")
            n["grid"].fail(fmt::format("unknown grid {} (known: sparse, dense)", quoted_input(kind)));
        sparse = kind == "sparse";
    }
    const int resolution = n.has("resolution")
                               ? n["resolution"].integer(2, sparse ? kMaxSparseMeshResolution : kMaxMeshResolution)
                               : kDefaultMeshResolution;
    const std::filesystem::path path = (catalog.base / name).lexically_normal();
    const auto key = std::tuple(path.string(), resolution, sparse);
    auto it = catalog.entries.find(key);
    if (it == catalog.entries.end()) {  // a file is checked and read once per scene
        check_file_allowed(file, path, catalog.base);
        const auto index = static_cast<std::uint32_t>(catalog.entries.size());
        it = catalog.entries.emplace(key, MeshCatalog::Entry{read_mesh_source(file, path, resolution, sparse), index}).first;
        if (!it->second.source->warning.empty())
            catalog.warnings.push_back(fmt::format("{}: {}: {}", file.where(), escaped(path.string(), kPathEchoLimit),
                                                   it->second.source->warning));
    }
    return make_mesh_edit(it->second.source, it->second.index);
}

// A level-set edit's own fields: the VDB file and the grid's name (optional when the file holds one).
Edit read_level_set_edit(const Node& n, MeshCatalog& catalog) {
    std::vector<std::string_view> allowed(kCommonEditFields.begin(), kCommonEditFields.end());
    allowed.insert(allowed.end(), {"file", "grid"});
    n.expect_keys(allowed, "a vdb level set");
    const Node file = n["file"];
    const std::string name = file.string();
    if (name.empty()) file.fail("must not be empty");
    const std::string grid = n.has("grid") ? n["grid"].string() : "";
    const std::filesystem::path path = (catalog.base / name).lexically_normal();
    const auto key = std::tuple(path.string() + '\n' + grid, -1, false);
    auto it = catalog.entries.find(key);
    if (it == catalog.entries.end()) {
        check_file_allowed(file, path, catalog.base);
        std::shared_ptr<MeshSource> source;
        try {
            source = make_level_set_source(read_level_set(path, grid), name);
        } catch (const InputError& e) {
            file.fail(escaped(e.what(), 2 * kPathEchoLimit));
        }
        const auto index = static_cast<std::uint32_t>(catalog.entries.size());
        it = catalog.entries.emplace(key, MeshCatalog::Entry{std::move(source), index}).first;
    }
    return make_mesh_edit(it->second.source, it->second.index);
}

bool names_level_set(const Node& n) {
    if (!n.has("primitive")) return false;
    const json& p = n["primitive"].value();
    return p.is_string() && p.get<std::string>() == "vdb";
}

Edit read_edit(const Node& n, MeshCatalog& meshes) {
    if (!n.value().is_object()) n.fail("expected an edit object");
    Edit e;
    if (names_level_set(n)) {
        e = read_level_set_edit(n, meshes);
    } else {
        e.primitive = read_primitive(n);
        if (e.primitive == Primitive::Mesh) e = read_mesh_edit(n, meshes);
        else e.params = read_params(n, e.primitive);
    }
    read_transform_fields(n, e.transform);
    if (n.has("op")) {
        const Node o = n["op"];
        const std::string name = o.string();
        const auto op = op_from_string(name);
        if (!op) o.fail(fmt::format("unknown operation {} (known: add, subtract, intersect)", quoted_input(name)));
        e.op = *op;
    }
    if (n.has("blend")) e.blend = n["blend"].non_negative();
    if (e.mesh && e.mesh->sparse)  // exact wherever the blend can reach: value < blend, in mesh units
        e.mesh->band = std::max(e.mesh->band, e.blend * lipschitz(e) / e.transform.scale);
    if (n.has("animation")) e.animation = read_animation(n["animation"]);
    return e;
}

Geometry read_geometry(const Node& n, MeshCatalog& meshes) {
    n.expect_object({"name", "edits"});
    Geometry g;
    g.name = n["name"].string();
    if (g.name.empty()) n["name"].fail("must not be empty");
    const Node edits = n["edits"];
    const std::size_t count = edits.array_size();
    if (count > SDF_MAX_EDITS)
        edits.fail(fmt::format("{} edits; a geometry holds at most {}", count, SDF_MAX_EDITS));
    g.edits.reserve(count);
    for (std::size_t i = 0; i < count; ++i) g.edits.push_back(read_edit(edits.at(i), meshes));
    return g;
}

Camera read_camera(const Node& n) {
    n.expect_object({"orbit", "look_at", "fov_deg"});
    Camera c;
    if (n.has("orbit") == n.has("look_at")) n.fail("needs exactly one of \"orbit\" and \"look_at\"");
    if (n.has("orbit")) {
        const Node o = n["orbit"];
        o.expect_object({"target", "distance", "yaw_deg", "pitch_deg"});
        c.kind = Camera::Kind::Orbit;
        if (o.has("target")) c.target = o["target"].vec3();
        c.distance = o["distance"].positive();
        if (o.has("yaw_deg")) c.yaw_deg = o["yaw_deg"].number();
        if (o.has("pitch_deg")) {
            c.pitch_deg = o["pitch_deg"].number();
            if (std::abs(c.pitch_deg) >= 90.0) o["pitch_deg"].fail("must lie strictly between -90 and 90");
        }
    } else {
        const Node l = n["look_at"];
        l.expect_object({"eye", "target", "up"});
        c.kind = Camera::Kind::LookAt;
        c.eye = l["eye"].vec3();
        c.target = l["target"].vec3();
        if (l.has("up")) c.up = l["up"].nonzero_vec3();
        if (glm::length(c.target - c.eye) == 0.0) l["target"].fail("must differ from eye");
        if (glm::length(glm::cross(c.target - c.eye, c.up)) == 0.0) l["up"].fail("must not be parallel to the view direction");
    }
    if (n.has("fov_deg")) {
        c.fov_deg = n["fov_deg"].positive();
        if (c.fov_deg >= 180.0) n["fov_deg"].fail("must be below 180");
    }
    return c;
}

Light read_light(const Node& n) {
    n.expect_object({"direction", "color", "intensity"});
    Light l;
    if (n.has("direction")) l.direction = n["direction"].nonzero_vec3();
    if (n.has("color")) {
        const Node c = n["color"];
        l.color = c.vec3();
        for (int i = 0; i < 3; ++i)
            if (l.color[i] < 0.0) c.at(static_cast<std::size_t>(i)).fail("must be >= 0");
    }
    if (n.has("intensity")) l.intensity = n["intensity"].non_negative();
    return l;
}

// A camera that sees the whole scene: orbit around the bounds' centre.
Camera default_camera(const Scene& s) {
    Aabb all;
    for (const Object& o : s.objects) all.grow(bounds(s, o));
    Camera c;
    if (all.empty()) return c;
    c.target = all.centre();
    const double radius = 0.5 * glm::length(all.extent());
    c.distance = std::max(radius / std::sin(glm::radians(c.fov_deg) * 0.5), 1e-3);
    return c;
}

std::string line_column(std::string_view text, std::size_t byte) {
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
        if (text[i] == '\n') { ++line; col = 1; } else { ++col; }
    }
    return fmt::format("line {}, column {}", line, col);
}

Scene read_scene(const json& j, std::string_view origin, const std::filesystem::path& base) {
    const Node root(j, "", origin);
    root.expect_object({"version", "name", "time", "geometries", "objects", "camera", "light"});
    if (root.has("version")) {
        const int v = root["version"].integer(0, 1 << 20);
        if (v != kSceneFormatVersion) root["version"].fail(fmt::format("unsupported version {} (this build reads {})", v, kSceneFormatVersion));
    }
    Scene s;
    if (root.has("name")) s.name = root["name"].string();
    if (root.has("time")) s.time = root["time"].number();
    const Node geos = root["geometries"];
    const std::size_t ng = geos.array_size();
    if (ng == 0) geos.fail("needs at least one geometry");
    std::map<std::string, std::size_t> by_name;
    MeshCatalog meshes{base, {}, {}};
    for (std::size_t i = 0; i < ng; ++i) {
        const Node g = geos.at(i);
        s.geometries.push_back(read_geometry(g, meshes));
        if (!by_name.emplace(s.geometries.back().name, i).second)
            g["name"].fail(fmt::format("duplicate geometry name {}", quoted_input(s.geometries.back().name)));
    }
    if (root.has("objects")) {
        const Node objs = root["objects"];
        const std::size_t no = objs.array_size();
        for (std::size_t i = 0; i < no; ++i) {
            const Node o = objs.at(i);
            o.expect_object({"name", "geometry", "position", "rotation", "scale"});
            Object obj;
            const Node gname = o["geometry"];
            const std::string name = gname.string();
            const auto it = by_name.find(name);
            if (it == by_name.end()) gname.fail(fmt::format("no geometry named {}", quoted_input(name)));
            obj.geometry = it->second;
            obj.name = o.has("name") ? o["name"].string() : name;
            read_transform_fields(o, obj.transform);
            s.objects.push_back(obj);
        }
    } else {
        for (std::size_t i = 0; i < ng; ++i) s.objects.push_back(Object{s.geometries[i].name, i, Transform{}});
    }
    s.camera = root.has("camera") ? read_camera(root["camera"]) : default_camera(scene_at(s, s.time));
    if (root.has("light")) s.light = read_light(root["light"]);
    s.warnings = std::move(meshes.warnings);
    return s;
}


// SAX pass that follows the JSON path while parsing, so that a syntax error or a number that
// overflows a double is reported with the place it occurred, as well as the line and column.
class PathTracker : public nlohmann::json_sax<json> {
public:
    PathTracker(std::string_view text, std::string_view origin) : text_(text), origin_(origin) {}
    std::string error;

    bool null() override { return value(); }
    bool boolean(bool) override { return value(); }
    bool number_integer(number_integer_t) override { return value(); }
    bool number_unsigned(number_unsigned_t) override { return value(); }
    bool number_float(number_float_t, const string_t&) override { return value(); }
    bool string(string_t&) override { return value(); }
    bool binary(binary_t&) override { return value(); }
    bool start_object(std::size_t) override { stack_.push_back({false, 0, "", {}}); return true; }
    bool key(string_t& k) override {
        Level& level = stack_.back();
        level.key = k;
        if (!level.keys.insert(k).second) {
            error = fmt::format("{}: {}: duplicate key", origin_, path());
            return false;
        }
        return true;
    }
    bool end_object() override { stack_.pop_back(); return value(); }
    bool start_array(std::size_t) override { stack_.push_back({true, 0, "", {}}); return true; }
    bool end_array() override { stack_.pop_back(); return value(); }
    bool parse_error(std::size_t position, const std::string& token, const nlohmann::detail::exception& ex) override {
        const std::string where = line_column(text_, position ? position - 1 : 0);
        if (ex.id == 406) {  // out_of_range: number overflow
            error = fmt::format("{}: {}: number is not finite: {} ({})", origin_, path(), escaped(token), where);
            return false;
        }
        std::string msg = ex.what();
        const auto cut = msg.find("syntax error");
        if (cut != std::string::npos) msg = msg.substr(cut);
        const bool truncated = position >= text_.size();
        error = fmt::format("{}: {}: invalid JSON at {}: {}{}", origin_, path(), where, escaped(msg, 200),
                            truncated ? " (is the file truncated?)" : "");
        return false;
    }

private:
    struct Level { bool array; std::size_t index; std::string key; std::set<std::string> keys; };
    bool value() {
        if (!stack_.empty() && stack_.back().array) ++stack_.back().index;
        return true;
    }
    std::string path() const {
        std::string p;
        for (const Level& l : stack_) p += "/" + (l.array ? std::to_string(l.index) : l.key);
        return p.empty() ? "/" : shortened_path(p);
    }
    std::string_view text_;
    std::string_view origin_;
    std::vector<Level> stack_;
};

}  // namespace

json parse_json_text(std::string_view text, std::string_view origin) {
    const std::string shown = escaped(origin, kPathEchoLimit);
    PathTracker tracker(text, shown);
    if (!json::sax_parse(text.begin(), text.end(), &tracker)) throw InputError(tracker.error);
    return json::parse(text.begin(), text.end());
}

json load_json(const std::filesystem::path& path) { return parse_json_text(read_file(path), path.string()); }

void allow_mesh_folders(std::vector<std::filesystem::path> folders) {
    const std::scoped_lock lock(allowed_folders_mutex);
    allowed_folders = std::move(folders);
}

Edit edit_from_json(const json& j, std::string_view origin, std::string_view path) {
    const std::string shown = escaped(origin, kPathEchoLimit);  // the node keeps a view of it
    const Node n(j, std::string(path), shown);
    if (!n.value().is_object()) n.fail("expected an edit object");
    if (names_level_set(n) || (n.has("primitive") && n["primitive"].value() == "mesh"))
        n.fail("a mesh or level-set edit cannot be added here: give it in the scene file");
    MeshCatalog none;
    return read_edit(n, none);
}

Scene parse_scene(std::string_view text, std::string_view origin, const std::filesystem::path& base) {
    return read_scene(parse_json_text(text, origin), escaped(origin, kPathEchoLimit), base);
}

Scene scene_from_json(const json& j, std::string_view origin, const std::filesystem::path& base) {
    return read_scene(j, escaped(origin, kPathEchoLimit), base);
}

Scene load_scene(const std::filesystem::path& path) {
    return parse_scene(read_file(path), path.string(), path.parent_path());
}

namespace {

json vec(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }

void write_transform_fields(json& j, const Transform& t) {
    if (t.translation != glm::dvec3(0.0)) j["position"] = vec(t.translation);
    if (t.rotation != glm::dquat(1.0, 0.0, 0.0, 0.0))
        j["rotation"] = json::array({t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w});
    if (t.scale != 1.0) j["scale"] = t.scale;
}

json edit_to_json(const Edit& e) {
    json j;
    j["primitive"] = std::string(to_string(e.primitive));
    const auto& p = e.params;
    switch (e.primitive) {
        case Primitive::Sphere: j["radius"] = p[0]; break;
        case Primitive::Box: j["half_extents"] = {p[0], p[1], p[2]}; break;
        case Primitive::RoundBox: j["half_extents"] = {p[0], p[1], p[2]}; j["rounding"] = p[3]; break;
        case Primitive::Torus: j["major_radius"] = p[0]; j["minor_radius"] = p[1]; break;
        case Primitive::Capsule: j["half_length"] = p[0]; j["radius"] = p[1]; break;
        case Primitive::Cylinder: j["half_height"] = p[0]; j["radius"] = p[1]; break;
        case Primitive::Cone: j["half_height"] = p[0]; j["radius_bottom"] = p[1]; j["radius_top"] = p[2]; break;
        case Primitive::Ellipsoid: j["radii"] = {p[0], p[1], p[2]}; break;
        case Primitive::Menger: j["half_size"] = p[0]; j["iterations"] = static_cast<int>(p[1]); break;
        case Primitive::Mesh:
            if (e.mesh->level_set()) {
                j["primitive"] = "vdb";
                j["file"] = e.mesh->file;
                j["grid"] = e.mesh->grid;
                break;
            }
            j["file"] = e.mesh->file;
            if (e.mesh->resolution != kDefaultMeshResolution) j["resolution"] = e.mesh->resolution;
            if (!e.mesh->sparse) j["grid"] = "dense";
            break;
    }
    write_transform_fields(j, e.transform);
    if (e.op != Op::Add) j["op"] = std::string(to_string(e.op));
    if (e.blend != 0.0) j["blend"] = e.blend;
    if (e.animation) {
        const Animation& a = *e.animation;
        json an = json::object();
        if (a.velocity != glm::dvec3(0.0)) an["velocity"] = vec(a.velocity);
        if (a.acceleration != glm::dvec3(0.0)) an["acceleration"] = vec(a.acceleration);
        if (a.spin_rate != 0.0) { an["spin_axis"] = vec(a.spin_axis); an["spin_rate"] = a.spin_rate; }
        if (a.wrap_y) an["wrap_y"] = {(*a.wrap_y)[0], (*a.wrap_y)[1]};
        j["animation"] = an;
    }
    return j;
}

}  // namespace

json scene_to_json(const Scene& s) {
    json j;
    j["version"] = kSceneFormatVersion;
    j["name"] = s.name;
    j["time"] = s.time;
    json geos = json::array();
    for (const Geometry& g : s.geometries) {
        json edits = json::array();
        for (const Edit& e : g.edits) edits.push_back(edit_to_json(e));
        geos.push_back({{"name", g.name}, {"edits", edits}});
    }
    j["geometries"] = geos;
    json objs = json::array();
    for (const Object& o : s.objects) {
        json oj;
        oj["name"] = o.name;
        oj["geometry"] = s.geometries.at(o.geometry).name;
        write_transform_fields(oj, o.transform);
        objs.push_back(oj);
    }
    j["objects"] = objs;
    json cam;
    if (s.camera.kind == Camera::Kind::Orbit)
        cam["orbit"] = {{"target", vec(s.camera.target)}, {"distance", s.camera.distance},
                        {"yaw_deg", s.camera.yaw_deg}, {"pitch_deg", s.camera.pitch_deg}};
    else
        cam["look_at"] = {{"eye", vec(s.camera.eye)}, {"target", vec(s.camera.target)}, {"up", vec(s.camera.up)}};
    cam["fov_deg"] = s.camera.fov_deg;
    j["camera"] = cam;
    j["light"] = {{"direction", vec(s.light.direction)}, {"color", vec(s.light.color)}, {"intensity", s.light.intensity}};
    return j;
}

namespace {

bool is_flat(const json& j) {
    if (j.is_array()) return std::all_of(j.begin(), j.end(), [](const json& v) { return v.is_primitive(); });
    if (j.is_object())
        return std::all_of(j.begin(), j.end(), [](const json& v) { return v.is_primitive() || (v.is_array() && is_flat(v)) || (v.is_object() && is_flat(v)); });
    return true;
}

void format_into(std::string& out, const json& j, int indent, int depth) {
    const std::string one_line = j.dump(-1, ' ', false, json::error_handler_t::replace);
    if (!j.is_structured() || j.empty() || (is_flat(j) && one_line.size() <= 280)) {
        // nlohmann's compact dump, with a space after ':' and ',' for readability (outside strings).
        bool in_string = false, escaped = false;
        for (char c : one_line) {
            out += c;
            if (in_string) {
                if (escaped) escaped = false;
                else if (c == '\\') escaped = true;
                else if (c == '"') in_string = false;
            } else if (c == '"') {
                in_string = true;
            } else if (c == ',' || c == ':') {
                out += ' ';
            }
        }
        return;
    }
    const std::string pad(static_cast<std::size_t>(indent * (depth + 1)), ' ');
    const bool is_object = j.is_object();
    out += is_object ? "{\n" : "[\n";
    std::size_t i = 0;
    for (auto it = j.begin(); it != j.end(); ++it, ++i) {
        out += pad;
        if (is_object) out += json(it.key()).dump(-1, ' ', false, json::error_handler_t::replace) + ": ";
        format_into(out, *it, indent, depth + 1);
        out += i + 1 < j.size() ? ",\n" : "\n";
    }
    out += std::string(static_cast<std::size_t>(indent * depth), ' ') + (is_object ? "}" : "]");
}

}  // namespace

std::string format_json(const json& j, int indent) {
    std::string out;
    format_into(out, j, indent, 0);
    out += '\n';
    return out;
}

std::string format_scene(const Scene& s) { return format_json(scene_to_json(s)); }

void save_scene(const Scene& s, const std::filesystem::path& path) { write_file_atomic(path, format_scene(s)); }

}  // namespace sdfbrick
