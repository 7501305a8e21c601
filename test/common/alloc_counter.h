// Counting the global operator new of a test binary: a binary that links test/common/
// alloc_counter.cc replaces operator new/delete with versions that count every allocation, so that
// a test can check that a Step allocates nothing. Only for binaries of their own (the replacement
// is global).
#pragma once

/// Calls of the global operator new (and new[]) so far in this process.
long AllocationCount() noexcept;
