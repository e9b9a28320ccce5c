// Internal: gather and scatter of (t, z) pairs at the sweep's hull slots, one 8-byte load or store per
// lane, for the lane widths without hardware gathers (sweep_horizons.cpp's lanes4 and lanes8). Included
// inside such a namespace after it has defined kLanes, Floats, Ints, Points, and the layout:
//   Pairs (doubles, kLanes / 2 of them), kPairLane (the lanes read into the first register and into the
//   second), kFirstOfPair (the shuffle that takes t from the two registers; z is the one after it), and
//   kPairOfLow / kPairOfHigh (the shuffles that interleave t and z back into the two registers).
// No include guard, and no includes of its own: the file including it has them.
// NOLINTBEGIN(llvm-header-guard)

[[gnu::always_inline]] inline Points gather(const float* pairs, Ints index) {
    Pairs low;
    Pairs high;
    for (int l = 0; l < kLanes / 2; ++l) {
        std::memcpy(&low[l], pairs + 2 * index[kPairLane[0][l]], sizeof(double));
        std::memcpy(&high[l], pairs + 2 * index[kPairLane[1][l]], sizeof(double));
    }
    const auto a = bitCast<Floats>(low);
    const auto b = bitCast<Floats>(high);
    return {__builtin_shuffle(a, b, kFirstOfPair), __builtin_shuffle(a, b, kFirstOfPair + 1)};
}
[[gnu::always_inline]] inline void scatter(float* pairs, Ints index, const Points& p) {
    const auto low = bitCast<Pairs>(__builtin_shuffle(p.t, p.z, kPairOfLow));
    const auto high = bitCast<Pairs>(__builtin_shuffle(p.t, p.z, kPairOfHigh));
    for (int l = 0; l < kLanes / 2; ++l) {
        std::memcpy(pairs + 2 * index[kPairLane[0][l]], &low[l], sizeof(double));
        std::memcpy(pairs + 2 * index[kPairLane[1][l]], &high[l], sizeof(double));
    }
}

// NOLINTEND(llvm-header-guard)
