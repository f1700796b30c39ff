#include "base/barrier.h"

#include <exception>
#include <string>

namespace dc::base {

Status guarded(std::string_view what, const std::function<void()>& body) {
    try {
        body();
        return Status::success();
    } catch (const std::exception& e) {
        return Error{std::string(what) + ": " + e.what()};
    } catch (...) {
        return Error{std::string(what) + ": an exception of unknown type"};
    }
}

} // namespace dc::base
