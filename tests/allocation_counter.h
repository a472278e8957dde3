// Counts heap allocations (malloc, calloc, realloc, the aligned variants and so
// operator new) made anywhere in the process while a function runs. Linked only
// into the test executable that checks the allocation-free frames:
// allocation_counter.cc replaces the C library's allocation entry points, which
// shared libraries (CHOLMOD, OpenBLAS, libstdc++) also call.
#pragma once

#include <functional>

namespace tb::testing {

/// Number of allocation calls made while `f` ran.
long allocations_during(const std::function<void()>& f);

}  // namespace tb::testing
