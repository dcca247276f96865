// LargeBuffer (Mappers/Common/LargeBuffer.h) and PermuteInPlace: the buffer's array of 2 MB
// or more starts at a 2 MB boundary (only aligned 2 MB ranges can be huge pages), a smaller
// one comes from the heap or its own mapping, each holds what is written to it,
// moves without copying; the permutation gives element i element order[i]'s values and keeps
// the vector's memory.
#include "Mappers/Common/LargeBuffer.h"
#include "Mappers/Common/PermuteInPlace.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

using namespace raymappers;

TEST(LargeBuffer, HoldsItsValuesOnAHugePageBoundaryAndMoves)
{
  LargeBuffer<std::uint32_t> empty;
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_EQ(LargeBuffer<float>(0).data(), nullptr);
  const std::size_t n = 3000001;
  LargeBuffer<std::uint32_t> b(n);
  ASSERT_EQ(b.size(), n);
#if defined(__linux__)
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(b.data()) % (std::uintptr_t(2) << 20), 0u);
#endif
  for (std::size_t i = 0; i < n; ++i)
  {
    b[i] = static_cast<std::uint32_t>(i * 2654435761u);
  }
  const std::uint32_t* at = b.data();
  LargeBuffer<std::uint32_t> moved(std::move(b));
  EXPECT_EQ(moved.data(), at);
  EXPECT_EQ(b.size(), 0u);
  for (std::size_t i = 0; i < n; i += 997)
  {
    ASSERT_EQ(moved[i], static_cast<std::uint32_t>(i * 2654435761u)) << i;
  }
  moved = LargeBuffer<std::uint32_t>();
  EXPECT_EQ(moved.size(), 0u);
}

TEST(LargeBuffer, SmallArraysFromTheHeapMiddleOnesMappedAlignedAndReleasedTheirWay)
{
  // Below 128 KB from the heap, up to 2 MB mapped in 4 KB pages, beyond on a 2 MB boundary:
  // each 64-byte aligned, holding its values, moved and released as it was obtained (freeing
  // a mapped array as heap memory, or unmapping a heap one, aborts or corrupts the heap).
  for (const std::size_t n : { std::size_t(10), std::size_t(32767), std::size_t(32768),
         std::size_t(400000), std::size_t(524288), std::size_t(600000) })
  {
    std::vector<LargeBuffer<std::uint32_t>> buffers;
    for (int k = 0; k < 3; ++k)
    {
      LargeBuffer<std::uint32_t> b(n);
      ASSERT_EQ(b.size(), n);
      EXPECT_EQ(reinterpret_cast<std::uintptr_t>(b.data()) % 64, 0u) << n;
#if defined(__linux__)
      if (n * sizeof(std::uint32_t) >= (std::size_t(2) << 20))
      {
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(b.data()) % (std::uintptr_t(2) << 20), 0u);
      }
#endif
      for (std::size_t i = 0; i < n; ++i)
      {
        b[i] = static_cast<std::uint32_t>(i + n * k);
      }
      buffers.push_back(std::move(b));
    }
    for (int k = 0; k < 3; ++k)
    {
      ASSERT_EQ(buffers[k][n - 1], static_cast<std::uint32_t>(n - 1 + n * k)) << n;
    }
    buffers[1] = LargeBuffer<std::uint32_t>(n / 2 + 1); // the old array released
    EXPECT_EQ(buffers[1].size(), n / 2 + 1);
  }
}

TEST(PermuteInPlace, ElementIBecomesElementOrderIAndTheVectorKeepsItsMemory)
{
  // Two arrays through one scratch, the second wider (the scratch grows) and of another
  // type: each element i takes element order[i]'s values.
  const std::size_t n = 200003;
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), std::mt19937(4));
  std::vector<std::uint32_t> ids(n);
  std::iota(ids.begin(), ids.end(), 0u);
  std::vector<float> triples(3 * n);
  for (std::size_t i = 0; i < triples.size(); ++i)
  {
    triples[i] = static_cast<float>(i);
  }
  const float* memory = triples.data();
  PermuteScratch scratch;
  permuteInPlace(ids, order.data(), scratch);
  permuteInPlace(triples, order.data(), scratch, 3);
  EXPECT_EQ(triples.data(), memory);
  for (std::size_t i = 0; i < n; ++i)
  {
    ASSERT_EQ(ids[i], order[i]) << i;
    for (std::size_t w = 0; w < 3; ++w)
    {
      ASSERT_EQ(triples[3 * i + w], static_cast<float>(3 * order[i] + w)) << i;
    }
  }
}
