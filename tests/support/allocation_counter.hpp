// Counts heap allocations in a scope, to prove that real-time steps never allocate.
// Link the object library lieservo_allocation_counter (tests/CMakeLists.txt). It counts, while
// an AllocationCounter is alive, every operator new (a replaced global operator new/delete,
// C++17 [replacement.functions]) or, under AddressSanitizer or ThreadSanitizer, every
// allocation the sanitizer's allocator sees (its malloc hook; operator new stays the
// sanitizer's). Catch2's own allocations happen outside the scope.
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
