// Output files that appear only when the whole run succeeded: each is written under a
// temporary name next to its destination and renamed into place at the end, so a refusal or
// a crash leaves no partial file and an existing file (the input, with --overwrite-input)
// is replaced in one step.
#pragma once

#include <string>
#include <vector>

namespace geofilter::cli {

// Whether two paths name the same file: same spelling after resolving ".", "..", symbolic
// links and the working directory, or (for files that exist) the same inode, so hard links
// count too.
bool same_file(const std::string& a, const std::string& b);

class PendingOutputs {
public:
    PendingOutputs() = default;
    PendingOutputs(const PendingOutputs&) = delete;
    PendingOutputs& operator=(const PendingOutputs&) = delete;
    ~PendingOutputs();  // removes what was not committed

    // A temporary path in `destination`'s directory, ending like it (writers choose the
    // format by extension). Throws Error when the directory is missing or the destination
    // is a directory.
    std::string reserve(const std::string& destination);
    // Renames every temporary into place. Throws Error (and removes the rest) on failure.
    void commit();

private:
    struct Entry {
        std::string temporary, destination;
    };
    std::vector<Entry> entries_;
};

} // namespace geofilter::cli
