// An uninitialized array for the temporaries of a build over millions of items (sort keys,
// permutations, gathered copies): memory mapped for the array alone and, on Linux, marked
// for transparent huge pages (madvise(MADV_HUGEPAGE), which the kernel honours in its
// default "madvise" mode), so that first touching its bytes faults once per 2 MB page instead
// of once per 4 KB page, and nothing writes its bytes before the build does (a std::vector
// value-initializes them). Page faults dominate such builds on virtual machines: the CGT grid
// of a 10-million-sphere Plummer set built in 1350 ms with its temporaries in std::vector and
// in 467 ms with them here (raymappers-bench on this project's 2-core virtual machine).
// An array smaller than a huge page is mapped as it is, in 4 KB pages (marked, its first
// touch would fault in and clear a whole 2 MB page). One below 128 KB (glibc's own
// threshold for mapping) comes from the heap: unmapping an array in a process whose other
// threads ran on other cores flushes their TLBs by interrupts, and the builds of small sets
// (the 1,102-atom protein 2LYZ) spent most of their time so. A failed mapping throws
// std::bad_alloc, as operator new does.
#ifndef RayMappers_LargeBuffer_h
#define RayMappers_LargeBuffer_h

#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace raymappers
{

template<typename T>
class LargeBuffer
{
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>,
    "LargeBuffer holds plain values: its bytes are never constructed");

public:
  LargeBuffer() = default;
  explicit LargeBuffer(std::size_t n) { allocate(n); }
  ~LargeBuffer() { release(); }
  LargeBuffer(const LargeBuffer&) = delete;
  LargeBuffer& operator=(const LargeBuffer&) = delete;
  LargeBuffer(LargeBuffer&& o) noexcept { swap(o); }
  LargeBuffer& operator=(LargeBuffer&& o) noexcept
  {
    swap(o);
    return *this;
  }

  T* data() { return Data; }
  const T* data() const { return Data; }
  std::size_t size() const { return Size; }
  T& operator[](std::size_t i) { return Data[i]; }
  const T& operator[](std::size_t i) const { return Data[i]; }

private:
  static constexpr std::size_t HugePage = std::size_t(2) << 20;
  static constexpr std::size_t HeapBytes = std::size_t(128) << 10;
  static constexpr std::align_val_t Alignment{ alignof(T) < 64 ? 64 : alignof(T) };
  void allocate(std::size_t n)
  {
    Size = n;
    if (n == 0)
    {
      return;
    }
    const std::size_t bytes = n * sizeof(T);
#if defined(__linux__)
    if (bytes >= HeapBytes)
    {
      map(bytes);
      return;
    }
#endif
    Base = ::operator new(bytes, Alignment);
    Data = static_cast<T*>(Base);
  }
#if defined(__linux__)
  void map(std::size_t bytes)
  {
    // Mapped one huge page larger, the array starting at a 2 MB boundary: only whole aligned
    // 2 MB ranges can be huge pages.
    const bool huge = bytes >= HugePage;
    Mapped = bytes + (huge ? HugePage : 0);
    void* p = mmap(nullptr, Mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED)
    {
      Mapped = 0;
      Size = 0;
      throw std::bad_alloc();
    }
    Base = p;
    Data = static_cast<T*>(p);
    if (huge)
    {
      const auto at = reinterpret_cast<std::uintptr_t>(p);
      const std::uintptr_t aligned = (at + HugePage - 1) & ~(HugePage - 1);
      madvise(reinterpret_cast<void*>(aligned), Mapped - (aligned - at), MADV_HUGEPAGE);
      Data = reinterpret_cast<T*>(aligned);
    }
  }
#endif
  void release()
  {
    if (!Base)
    {
      return;
    }
    if (Mapped > 0)
    {
#if defined(__linux__)
      munmap(Base, Mapped);
#endif
    }
    else
    {
      ::operator delete(Base, Alignment);
    }
    Base = nullptr;
    Data = nullptr;
    Size = 0;
    Mapped = 0;
  }
  void swap(LargeBuffer& o) noexcept
  {
    std::swap(Base, o.Base);
    std::swap(Data, o.Data);
    std::swap(Size, o.Size);
    std::swap(Mapped, o.Mapped);
  }

  void* Base = nullptr;
  T* Data = nullptr;
  std::size_t Size = 0;
  std::size_t Mapped = 0;
};

} // namespace raymappers

#endif
