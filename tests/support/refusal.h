// What a call refuses with: the message of the geofilter::Error it throws, or "" when it runs.
// "" rather than a sentence, so that no search for a word of the expected message can match
// a call that was not refused.
#pragma once

#include "core/types.h"

#include <functional>
#include <string>

namespace geofilter {

inline std::string refusal_message(const std::function<void()>& call) {
    try {
        call();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

} // namespace geofilter
