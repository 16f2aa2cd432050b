#include "engine/file_io.h"

#include "engine/error.h"

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <unistd.h>

namespace arbor::engine {

std::string read_file(const std::string& path, std::uint64_t max_bytes) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw InputError(path, 0, std::string("cannot open (") + std::strerror(errno) + ")");
    std::string data;
    char buf[1 << 16];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) {
        data.append(buf, n);
        if (data.size() > max_bytes) {
            std::fclose(f);
            throw InputError(path, 0, "file is larger than " + std::to_string(max_bytes) + " bytes");
        }
    }
    const bool failed = std::ferror(f);
    std::fclose(f);
    if (failed) throw InputError(path, 0, "read error (is it a directory?)");
    return data;
}

namespace {

/// The temporaries of the live, uncommitted AtomicFiles.
struct Unfinished {
    std::timed_mutex mu;
    std::multiset<std::string> paths;
};

Unfinished& unfinished() {
    static Unfinished* u = new Unfinished;  // never destroyed: an exit path may still read it
    return *u;
}

void forget_unfinished(const std::string& path) {
    Unfinished& u = unfinished();
    std::lock_guard lock(u.mu);
    if (const auto it = u.paths.find(path); it != u.paths.end()) u.paths.erase(it);
}

}  // namespace

AtomicFile::AtomicFile(std::string target) : target_(std::move(target)) {
    temp_ = target_ + ".tmp-" + std::to_string(::getpid());
    Unfinished& u = unfinished();
    std::lock_guard lock(u.mu);
    u.paths.insert(temp_);
}

AtomicFile::~AtomicFile() {
    if (!committed_) {
        std::remove(temp_.c_str());
        forget_unfinished(temp_);
    }
}

void AtomicFile::commit() {
    if (std::rename(temp_.c_str(), target_.c_str()) != 0)
        throw InputError(target_, 0, std::string("cannot write (") + std::strerror(errno) + ")");
    committed_ = true;
    forget_unfinished(temp_);
}

void remove_unfinished_files() {
    Unfinished& u = unfinished();
    std::unique_lock lock(u.mu, std::chrono::milliseconds(50));
    if (!lock.owns_lock()) return;
    for (const std::string& path : u.paths) ::unlink(path.c_str());
}

void write_file_atomic(const std::string& path, std::string_view bytes) {
    AtomicFile out(path);
    {
        std::ofstream f(out.temp_path(), std::ios::binary);
        if (!f) throw InputError(path, 0, std::string("cannot write (") + std::strerror(errno) + ")");
        f.write(bytes.data(), std::streamsize(bytes.size()));
        f.flush();
        if (!f) throw InputError(path, 0, "write failed (disk full?)");
    }
    out.commit();
}

}  // namespace arbor::engine
