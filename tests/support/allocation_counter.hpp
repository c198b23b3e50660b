// Counts heap allocations in a scope, to prove that real-time steps never allocate.
// Link the object library lieservo_allocation_counter (tests/CMakeLists.txt): it replaces the
// global operator new/delete of the executable (C++17 [replacement.functions]) with versions
// that count while an AllocationCounter is alive. Catch2's own allocations happen outside it.
#pragma once

namespace lieservo::test {

class AllocationCounter {
 public:
  AllocationCounter() noexcept;  ///< resets the count and starts counting
  ~AllocationCounter();          ///< stops counting
  AllocationCounter(const AllocationCounter&) = delete;
  AllocationCounter& operator=(const AllocationCounter&) = delete;
  /// Allocations (every form of operator new) since construction.
  long count() const noexcept;
};

}  // namespace lieservo::test
