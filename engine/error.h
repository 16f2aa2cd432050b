#pragma once
/// InputError: the one exception for bad user input (files, options). Its message is a single line
/// naming the file (and line) or option and the problem (line breaks in it are escaped);
/// apps/arbor/main.cpp prints it and exits 1.
#include <stdexcept>
#include <string>

#include "engine/one_line.h"

namespace arbor::engine {

class InputError : public std::runtime_error {
public:
    explicit InputError(const std::string& what) : std::runtime_error(one_line(what)) {}
    /// "FILE:LINE: problem" (LINE omitted when 0).
    InputError(const std::string& file, std::size_t line, const std::string& problem)
        : std::runtime_error(
              one_line(line ? file + ":" + std::to_string(line) + ": " + problem : file + ": " + problem)) {}
};

}  // namespace arbor::engine
