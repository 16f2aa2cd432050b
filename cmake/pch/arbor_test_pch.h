// The test files' precompiled header (cmake/ArborPch.cmake): the library's, and doctest.
#pragma once
#include "arbor_pch.h"
#include <doctest/doctest.h>
