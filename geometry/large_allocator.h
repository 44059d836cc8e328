#pragma once
/// @file Internal: an allocator for the large arrays of a scene (swept volumes, node volumes, the
/// front), backed by transparent huge pages where the system offers them.
///
/// A scene's arrays run to tens of megabytes, written in full every step. Touched for the
/// first time in 4 KiB pages, every page costs a fault (in virtual machines several
/// microseconds each); in 2 MiB huge
/// pages the same memory takes a few hundred faults, and the traversal's random reads miss
/// the TLB less. Arrays of at least half a huge page are therefore allocated on 2 MiB
/// boundaries, and their whole huge pages advised MADV_HUGEPAGE (Linux; a hint: where the
/// kernel declines, nothing changes but the alignment). The last partial huge page is advised
/// only when the array fills at least three quarters of it (huge_part): otherwise it stays in
/// 4 KiB pages, touched only as far as the array reaches, so a huge page never holds more than
/// 512 KiB of nothing. (At half, the arrays of 1 to 1.5 MiB of a 92K-triangle scene held 2 MiB
/// each, 5-8 MB of its 105.) Smaller arrays, and every array elsewhere, come from operator new.
/// Memory is returned to where it came from; the allocator is stateless, so any two compare equal.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <type_traits>
#include <new>
#include <utility>
#include <vector>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace mccd::detail {

inline constexpr std::size_t kHugePage = std::size_t(2) << 20;
inline constexpr std::size_t kHugeMin = kHugePage / 2;

/// The bytes of an array of `bytes` (on a huge page boundary) advised huge: its whole huge
/// pages, and the last partial one when the array fills at least three quarters of it (at most
/// 512 KiB of a huge page then holds nothing, against up to 384 faults of 4 KiB pages).
constexpr std::size_t huge_part(std::size_t bytes) {
  const std::size_t whole = bytes / kHugePage * kHugePage;
  return bytes - whole >= kHugePage / 4 * 3 ? whole + kHugePage : whole;
}

/// The first huge-page boundary at or above address `a`.
constexpr std::uintptr_t huge_boundary_above(std::uintptr_t a) { return (a + kHugePage - 1) / kHugePage * kHugePage; }

/// Advises MADV_HUGEPAGE on the whole 2 MiB pages inside [p, p + bytes) (memory allocated
/// elsewhere, such as a std::vector handed to the caller, before its first touch). A hint:
/// where the kernel declines, or elsewhere than Linux, nothing changes.
inline void advise_huge_pages([[maybe_unused]] void* p, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__)
  const auto begin = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t first = huge_boundary_above(begin);
  const std::uintptr_t last = (begin + bytes) / kHugePage * kHugePage;
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#endif
}

/// Backs the whole 4 KiB pages inside [p, p + bytes) at once (MADV_POPULATE_WRITE, Linux 5.14
/// and later) for memory about to be written in full: the kernel fills them in one call
/// instead of one fault per page (each costly in a virtual machine). Huge pages advised
/// before are backed as huge pages. A hint: where the kernel declines, the pages fault in
/// when first written, as without it.
inline void populate_pages([[maybe_unused]] void* p, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__)
  constexpr int kPopulateWrite = 23;  // MADV_POPULATE_WRITE (older headers lack the name)
  constexpr std::uintptr_t kPage = 4096;
  const auto begin = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t first = (begin + kPage - 1) / kPage * kPage;
  const std::uintptr_t last = (begin + bytes) / kPage * kPage;
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, kPopulateWrite);
#endif
}

/// Reserves room for `n` elements in an empty std::vector of any allocator and backs the pages
/// they reach at once (populate_pages), for an array about to be written in full: in a virtual
/// machine a fault costs about four times what backing the same page in one call does. Only
/// those pages: what the array will not reach stays untouched (no huge pages, unlike
/// reserve_huge). Below 64 KiB, a plain reserve.
template <class T, class A>
void reserve_backed(std::vector<T, A>& v, std::size_t n) {
  const bool fresh = v.empty() && v.capacity() < n;
  v.reserve(n);
  if (fresh && n * sizeof(T) >= (std::size_t(64) << 10)) populate_pages(v.data(), n * sizeof(T));
}

/// An empty std::vector made `n` copies of `value`, its pages backed in one call.
template <class T, class A>
void backed_assign(std::vector<T, A>& v, std::size_t n, const std::type_identity_t<T>& value = T()) {
  reserve_backed(v, n);
  v.assign(n, value);
}

/// A copy of `v` whose pages are backed in one call (reserve_backed) rather than faulted in.
template <class T, class A>
std::vector<T, A> backed_copy(const std::vector<T, A>& v) {
  std::vector<T, A> c;
  reserve_backed(c, v.size());
  c.assign(v.begin(), v.end());
  return c;
}
/// The same for positions (a type keeping its numbers in one vector, xyz(), made from one by
/// from_xyz(): Positions, whose public header does not see this one).
template <class P>
  requires requires(const P& p) { P::from_xyz(backed_copy(p.xyz())); }
P backed_copy(const P& p) {
  return P::from_xyz(backed_copy(p.xyz()));
}

/// Reserves room for `n` elements in an empty std::vector of any allocator (one handed to the
/// caller) and advises its huge pages before their first touch, by the rule of huge_part: the
/// capacity is grown by one huge page so that the last page the `n` elements reach lies inside
/// it. Below half a huge page, a plain reserve. With `populate`, the pages the `n` elements
/// reach are backed at once (populate_pages); without, the caller backs them (in parallel).
template <class T, class A>
void reserve_huge(std::vector<T, A>& v, std::size_t n, bool populate = true) {
  const std::size_t bytes = n * sizeof(T);
  if (bytes < kHugeMin || !v.empty()) {
    v.reserve(n);
    return;
  }
  v.reserve(n + kHugePage / sizeof(T) + 1);
#if defined(__linux__)
  const auto begin = reinterpret_cast<std::uintptr_t>(v.data());
  const std::uintptr_t first = huge_boundary_above(begin);
  const std::uintptr_t end = begin + bytes;
  if (end <= first) return;
  const std::uintptr_t last = first + huge_part(end - first);
  madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#endif
  if (populate) populate_pages(v.data(), bytes);
}

template <class T>
struct LargeAllocator {
  using value_type = T;
  LargeAllocator() = default;
  template <class U>
  LargeAllocator(const LargeAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    // Beyond a quarter of the address space no allocation can succeed (and the rounding below
    // stays in range).
    if (n > (std::size_t(-1) >> 2) / sizeof(T)) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
#if defined(__linux__)
    if (bytes >= kHugeMin) {
      const std::size_t size = (bytes + kHugePage - 1) / kHugePage * kHugePage;
      void* p = std::aligned_alloc(kHugePage, size);
      if (!p) throw std::bad_alloc();
      madvise(p, huge_part(bytes), MADV_HUGEPAGE);  // a hint; its failure changes nothing
      return static_cast<T*>(p);
    }
#endif
    return static_cast<T*>(::operator new(bytes, std::align_val_t(alignof(T) > 16 ? alignof(T) : 16)));
  }

  void deallocate(T* p, std::size_t n) noexcept {
#if defined(__linux__)
    if (n * sizeof(T) >= kHugeMin) {
      std::free(p);
      return;
    }
#endif
    ::operator delete(p, std::align_val_t(alignof(T) > 16 ? alignof(T) : 16));
  }

  /// Elements are default-initialised (left as they are for the trivial types stored here):
  /// resizing touches no memory, so a caller can write it first where it wants, in parallel
  /// (first_touch).
  template <class U>
  void construct(U* p) noexcept(noexcept(::new (static_cast<void*>(p)) U)) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }

  template <class U>
  bool operator==(const LargeAllocator<U>&) const noexcept {
    return true;
  }
};

/// A std::vector of large-array storage. resize() leaves new trivial elements uninitialised.
template <class T>
using LargeVector = std::vector<T, LargeAllocator<T>>;

/// Zeroes `v` in chunks handed to `for_chunks(n, body)` (body(begin, end) over element
/// indices), so that a parallel loop spreads the first touch of its pages, and with it the
/// kernel's backing and zeroing, over threads; each chunk's pages are backed in one call
/// (populate_pages) before they are written.
template <class T, class ForChunks>
void first_touch(LargeVector<T>& v, const ForChunks& for_chunks) {
  static_assert(std::is_trivially_copyable_v<T>);
  T* data = v.data();
  for_chunks(v.size(), [data](std::size_t b, std::size_t e) {
    if (e <= b) return;
    populate_pages(data + b, (e - b) * sizeof(T));
    std::memset(static_cast<void*>(data + b), 0, (e - b) * sizeof(T));
  });
}

}  // namespace mccd::detail
