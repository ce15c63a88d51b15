// core/base/error.h: pathview's one error type for bad input (files, CLI, parameters) and device failures.
// Messages read "<file>:<line>: what is wrong; what was expected". The hot path never throws.
#pragma once

#include <stdexcept>
#include <string>

namespace pv {

struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace pv
