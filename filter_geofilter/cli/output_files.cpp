#include "output_files.h"

#include "core/types.h"

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>

namespace geofilter::cli {

namespace fs = std::filesystem;

bool same_file(const std::string& a, const std::string& b) {
    std::error_code ec_a, ec_b;
    if (fs::exists(a, ec_a) && fs::exists(b, ec_b)) {
        std::error_code ec;
        if (fs::equivalent(a, b, ec)) return true;
    }
    std::error_code ec1, ec2;
    const fs::path ca = fs::weakly_canonical(fs::absolute(a), ec1), cb = fs::weakly_canonical(fs::absolute(b), ec2);
    return !ec1 && !ec2 && ca == cb;
}

PendingOutputs::~PendingOutputs() {
    for (const auto& e : entries_) std::remove(e.temporary.c_str());
}

std::string PendingOutputs::reserve(const std::string& destination) {
    const fs::path dest(destination);
    std::error_code ec;
    if (fs::is_directory(dest, ec)) throw Error("'" + destination + "' is a directory, not a file name");
    const fs::path dir = dest.has_parent_path() ? dest.parent_path() : fs::path(".");
    if (!fs::is_directory(dir, ec)) throw Error("cannot write '" + destination + "': no directory " + dir.string());
    if (access(dir.c_str(), W_OK) != 0)
        throw Error("cannot write '" + destination + "': directory " + dir.string() + " is not writable");
    // Hidden, and unique per process and per call, so parallel runs never share one; the
    // extension stays, as the writer picks the format by it.
    const std::string extension = dest.extension().string();
    const fs::path temporary = dir / ("." + dest.stem().string() + ".geofilter-" + std::to_string(getpid()) + "-" +
                                      std::to_string(entries_.size()) + extension);
    entries_.push_back({temporary.string(), destination});
    return temporary.string();
}

void PendingOutputs::commit() {
    for (auto& e : entries_) {
        if (std::rename(e.temporary.c_str(), e.destination.c_str()) != 0)
            throw Error("cannot move the finished file to '" + e.destination + "': " + std::strerror(errno));
        e.temporary.clear();  // committed: the destructor leaves it alone
    }
    entries_.clear();
}

} // namespace geofilter::cli
