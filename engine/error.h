#pragma once
/// InputError: the one exception for bad user input (files, options). Its message is a single line
/// naming the file (and line) or option and the problem; apps/arbor/main.cpp prints it and exits 1.
#include <stdexcept>
#include <string>

namespace arbor::engine {

class InputError : public std::runtime_error {
public:
    explicit InputError(const std::string& what) : std::runtime_error(what) {}
    /// "FILE:LINE: problem" (LINE omitted when 0).
    InputError(const std::string& file, std::size_t line, const std::string& problem)
        : std::runtime_error(line ? file + ":" + std::to_string(line) + ": " + problem : file + ": " + problem) {}
};

}  // namespace arbor::engine
