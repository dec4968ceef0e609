// film.aovs (see aov_names.h).
#include "scene/aov_names.h"

#include <algorithm>

namespace penumbra {

std::vector<std::string> readAovNames(const JsonReader& list) {
    std::vector<std::string> names;
    for (size_t i = 0; i < list.size(); ++i) {
        const JsonReader item = list[i];
        std::string name = item.string();
        if (std::find(kAovNames.begin(), kAovNames.end(), name) == kAovNames.end()) {
            std::string known;
            for (std::string_view n : kAovNames) known += (known.empty() ? "" : ", ") + std::string(n);
            item.fail("unknown AOV \"" + name + "\" (known: " + known + ")");
        }
        if (std::find(names.begin(), names.end(), name) != names.end()) item.fail("AOV \"" + name + "\" given twice");
        names.push_back(std::move(name));
    }
    return names;
}

}  // namespace penumbra
