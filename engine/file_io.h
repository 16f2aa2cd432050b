#pragma once
/// File helpers: whole-file reads with clear errors, and atomic writes (temporary file + rename),
/// so that nothing a user wrote is ever left half-overwritten.
#include <cstdint>
#include <string>
#include <string_view>

namespace arbor::engine {

/// Reads a whole file; throws InputError("FILE: cannot open (reason)") and refuses files larger
/// than `max_bytes`.
std::string read_file(const std::string& path, std::uint64_t max_bytes = 1ull << 34);

/// A temporary path beside `target`; commit() renames it onto the target, and the destructor
/// removes the temporary if commit() was never reached (an exception on the way). Every
/// temporary of a live AtomicFile is also listed for remove_unfinished_files().
class AtomicFile {
public:
    explicit AtomicFile(std::string target);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    const std::string& temp_path() const { return temp_; }
    /// Renames the temporary onto the target; throws InputError when that fails.
    void commit();

private:
    std::string target_, temp_;
    bool committed_ = false;
};

/// Removes the temporary file of every AtomicFile not yet committed or destroyed. For a path that
/// ends the process without unwinding (an MPI job stopped by MPI_Abort or by its launcher), so
/// that no partial output is left behind. Thread-safe; gives up after 50 ms when another thread
/// holds the list (it may have crashed holding it).
void remove_unfinished_files();

/// Writes `bytes` to `path` atomically.
void write_file_atomic(const std::string& path, std::string_view bytes);

}  // namespace arbor::engine
