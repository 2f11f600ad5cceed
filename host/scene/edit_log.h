// An edit log: operations on a scene's geometries at given frames, the way a sculpting user changes
// a scene one stroke at a time. JSON lines, one operation per line (docs/frames.md):
//   {"frame": 3, "op": "append",  "geometry": "clay", "edits": [EDIT, ...]}   (or "edit": EDIT)
//   {"frame": 4, "op": "remove",  "geometry": "clay", "index": 12}
//   {"frame": 5, "op": "replace", "geometry": 0,      "index": 7, "edit": EDIT}
// EDIT is an edit object as scene files hold them (not a mesh or level set). Blank lines are skipped.
// Frames do not decrease from line to line; operations of one frame apply in line order.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.h"

namespace sdfbrick {

struct EditOp {
    enum class Kind { append, remove, replace };
    Kind kind = Kind::append;
    int frame = 0;
    std::size_t geometry = 0;
    std::size_t index = 0;    // remove, replace: the edit, as the operations before this one left the list
    std::vector<Edit> edits;  // append: one or more; replace: one
    std::size_t line = 0;     // 1-based, in the log
};
std::string_view to_string(EditOp::Kind k);

struct EditLog {
    std::string origin;  // the file, for messages
    std::vector<EditOp> ops;
};

// Parses a log against scene: geometry names and indices, and every edit index as the log's earlier
// operations leave the lists (so that applying the log in order cannot fail). Errors are InputErrors
// naming the origin, the line and the field ("strokes.jsonl:12: /index: no edit 40 in geometry
// \"clay\" (it has 38)").
EditLog parse_edit_log(std::string_view text, std::string_view origin, const Scene& scene);
EditLog load_edit_log(const std::filesystem::path& path, const Scene& scene);

// Applies one operation of a parsed log to scene (the scene it was parsed against, with the log's
// earlier operations applied).
void apply(Scene& scene, const EditOp& op);

}  // namespace sdfbrick
