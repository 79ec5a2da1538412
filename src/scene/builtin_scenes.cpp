#include <utility>
#include <vector>

#include "smokescan/core/error.hpp"
#include "smokescan/scene/scene_io.hpp"

namespace smokescan {

const std::vector<std::pair<std::string, std::string>>& builtinSceneTable();  // generated

std::vector<std::string> builtinSceneNames()
{
    std::vector<std::string> names;
    for (const auto& [name, text] : builtinSceneTable()) names.push_back(name);
    return names;
}

std::string builtinSceneText(const std::string& name)
{
    for (const auto& [n, text] : builtinSceneTable())
        if (n == name) return text;
    std::string all;
    for (const auto& n : builtinSceneNames()) all += (all.empty() ? "" : ", ") + n;
    throw Error(name, "no such built-in scene (built-in scenes: " + all + ")");
}

}  // namespace smokescan
