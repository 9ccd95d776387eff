#include "particles/colouring.h"

namespace moreau::particles::internal {

void Colouring::Assign(const CellList& cells) {
  const int* nb = cells.blocks_per_axis();
  const auto blocks = static_cast<std::size_t>(cells.blocks());
  std::vector<int> colour_of(blocks);
  colour_begin_.assign(kColours + 1, 0);
  for (std::size_t r = 0; r < blocks; ++r) {
    const std::int64_t b = cells.block_of_rank()[r];
    const int c[3] = {static_cast<int>(b % nb[0]), static_cast<int>((b / nb[0]) % nb[1]),
                      static_cast<int>(b / (static_cast<std::int64_t>(nb[0]) * nb[1]))};
    colour_of[r] = c[0] % 3 + 3 * (c[1] % 3) + 9 * (c[2] % 3);
    ++colour_begin_[static_cast<std::size_t>(colour_of[r]) + 1];
  }
  for (int c = 0; c < kColours; ++c) {
    colour_begin_[static_cast<std::size_t>(c) + 1] += colour_begin_[static_cast<std::size_t>(c)];
  }
  blocks_.assign(blocks, 0);
  std::vector<int> fill(colour_begin_.begin(), colour_begin_.end() - 1);
  for (std::size_t r = 0; r < blocks; ++r) {
    blocks_[static_cast<std::size_t>(fill[static_cast<std::size_t>(colour_of[r])]++)] =
        static_cast<int>(r);
  }
}

}  // namespace moreau::particles::internal
