// Internal: the sweep's SIMD kernel for one line group, written once for any lane count. It is included
// by sweep_horizons.cpp inside a namespace per lane width (4 for the baseline ISA, 8 for AVX2, 16 for
// AVX-512, the latter inside a `#pragma GCC target` region), after that namespace has defined:
//   kLanes, Floats and Ints (GCC vector types of kLanes lanes), kLaneIndex = {0, 1, ..., kLanes - 1},
//   struct Points { Floats t, z; }, any<kNative>(Ints) (whether any lane is set),
//   gather(const float*, Ints) / scatter(float*, Ints, const Points&) of (t, z) at hull slots,
//   kHeld (how many of each stack's top slots are held in registers: 4, or 7 where there are 32),
// and after DirectionPlan, NearStencil, PaddedRelief, GroupWork, kNear and kRun. No include guard, and
// no includes of its own: the file including it has them all.
// NOLINTBEGIN(llvm-header-guard)

[[gnu::always_inline]] inline Floats load(const float* p) {
    Floats v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
[[gnu::always_inline]] inline void store(float* p, Floats v) {
    std::memcpy(p, &v, sizeof v);
}
[[gnu::always_inline]] inline Floats splat(float x) {
    return Floats{} + x;
}
[[gnu::always_inline]] inline Floats max(Floats a, Floats b) {
    return a > b ? a : b;
}
[[gnu::always_inline]] inline Ints max(Ints a, Ints b) {
    return a > b ? a : b;
}
// The stack slot d of every lane: (t, z) pairs, lane l of slot d at 2 (d kLanes + l).
[[gnu::always_inline]] inline Ints slot(Ints d) {
    return d * kLanes + kLaneIndex;
}
[[gnu::always_inline]] inline Points select(Ints mask, const Points& a, const Points& b) {
    return {mask ? a.t : b.t, mask ? a.z : b.z};
}
// What the group's result holds: tan h, or with cosineWeights the direction's term of the
// cosine-weighted AO, cos^2 h = 1 / (1 + tan^2 h).
[[gnu::always_inline]] inline Floats result(Floats tanH, bool cosineWeights) {
    return cosineWeights ? 1.0f / (1.0f + tanH * tanH) : tanH;
}
// > 0 where c lies above the line through a and b (a.t < b.t).
[[gnu::always_inline]] inline Floats orient(const Points& a, const Points& b, const Points& c) {
    return (b.t - a.t) * (c.z - a.z) - (b.z - a.z) * (c.t - a.t);
}

// The near field of the group's texels at every step k into tan: tan h >= 0 over distances up to
// kNear steps (or R), and with atR (where R is beyond the near field) the point at exactly R.
template <bool kNative>
[[gnu::always_inline]] inline void nearFieldOfGroup(const float* zmap, const DirectionPlan& plan,
                                                    const NearStencil& stencil,
                                                    const DirectionPlan::Side* atR, bool cosineWeights,
                                                    float* tan) {
    const auto radius = static_cast<float>(plan.radius);
    const float cMajor = stencil.coefMajor;
    const float cMinor = stencil.coefMinor;
    for (int k = 0; k < plan.sizeA; ++k) {
        const float* p = zmap + plan.texelIndex[static_cast<std::size_t>(k)];
        const Floats zP = load(p);
        Floats best =
            max(cMajor * (load(p + stencil.aheadOffset) - zP) + cMinor * (load(p + stencil.sideOffset) - zP),
                Floats{});
        Floats z0 = zP;  // where the segment starts: the previous one's end
        for (const NearSegment& s : stencil.segments) {
            const float* c = p + s.offset;
            const Floats c00 = load(c);
            const Floats c10 = load(c + stencil.majorOffset);
            const Floats c01 = load(c + 1);
            const Floats c11 = load(c + stencil.majorOffset + 1);
            const Floats e = (c00 - c10) - (c01 - c11);
            const Floats z1 = c00 + (c10 - c00) * s.alpha1 + ((c01 - c00) + e * s.alpha1) * s.beta1;
            best = max(best, (z1 - zP) * s.invT1);
            if (s.t0 > 0.0f) {
                // Inside the cell the relief along the line is z(t) = qa + qb t + qc t^2 with
                // qc = e dA dB / (t1 - t0)^2; its elevation (z - zP) / t peaks where qc t^2 = qa - zP, when
                // that t lies inside the segment and the arc is concave: raiseByArcInterior's formula
                // (horizon_line.h), branch-free across the lanes.
                const float t0 = s.t0;
                const float t1 = s.t1;
                const Floats qc = e * s.twist;
                const Floats qb = (z1 - z0) * s.invLength - qc * (t0 + t1);
                // t0^2 < (qa - zP) / qc < t1^2 with qc < 0, multiplied out: no division.
                const Floats rise = z0 - qb * t0 - qc * (t0 * t0) - zP;
                // Where the peak lies inside, it raises best only if qb - best > 2 sqrt(rise qc), i.e.
                // qb > best and (qb - best)^2 > 4 rise qc (with a 2^-20 margin for rounding): the root is
                // taken only then.
                const Floats above = qb - best;
                const Ints inside = (qc < 0.0f) & (rise < qc * (t0 * t0)) & (rise > qc * (t1 * t1)) &
                                    (above > 0.0f) & (above * above > (4.0f - 0x1p-18f) * (rise * qc));
                if (any<kNative>(inside)) {
                    // The peak's elevation, qb - 2 sqrt(rise qc); the root is kept finite where unused.
                    Floats root = max(rise * qc, Floats{});
                    for (int l = 0; l < kLanes; ++l) root[l] = std::sqrt(root[l]);
                    best = inside ? max(best, qb - 2.0f * root) : best;
                }
            }
            z0 = z1;
        }
        if (atR != nullptr) {
            const DirectionPlan::Side& w = *atR;
            const auto kk = static_cast<std::size_t>(k);
            const float fr = w.boundaryFrac[kk];
            const float alpha = w.boundaryAlpha[kk];
            const float* c0 = zmap + w.boundaryIndex0[kk];
            const float* c1 = zmap + w.boundaryIndex1[kk];
            const Floats zR = (1.0f - alpha) * ((1.0f - fr) * load(c0) + fr * load(c0 + 1)) +
                              alpha * ((1.0f - fr) * load(c1) + fr * load(c1 + 1));
            best = max(best, (zR - zP) / radius);
        }
        store(tan + static_cast<std::ptrdiff_t>(k) * kLanes, result(best, cosineWeights));
    }
}

// Whether b lies higher than a as seen from q: above the line from a to q when q lies after both in
// t (side 0), or before both (side 1).
template <int kSide>
[[gnu::always_inline]] inline Ints seesHigher(const Points& q, const Points& a, const Points& b) {
    return (kSide == 0 ? orient(a, q, b) : orient(b, q, a)) > 0.0f;
}

// Each lane's upper hull on a stack, slot d at d kLanes + lane, with its top kHeld slots also in
// registers. A pop reads the slot under them, kHeld - 2 pops ahead of the test that would need it, so
// the read is not on the path that decides whether to pop again; and most tangents are found among
// them (tangent()). With 32 vector registers (AVX-512) 7 slots take 14 of them and beat 4; with 16
// (SSE2, AVX2) 7 slots spill, so those kernels hold 4 (docs/dev/occlusion-notes.md has the measurements).
static_assert(kHeld == 4 || kHeld == 7);
struct HullStack {
    float* points;
    Ints size{};
    Points top{};  // slots size, size - 1, ..., size - kHeld + 1
    Points second{};
    Points third{};
    Points fourth{};
    Points fifth{};  // these three only with kHeld = 7
    Points sixth{};
    Points seventh{};
};

// The vertex of each lane's upper hull that q sees highest, i.e. the tangent from q (the hull's points
// all lie on one side of q in t, its top nearest). The elevation seen from q rises along the hull from
// its top to that vertex and falls beyond, so the search walks down from the top: through the held
// slots first, then reading two slots a step, both before either comparison. The steps are written out:
// the same step as an always-inlined function or lambda made GCC 12's code slower overall
// (docs/dev/occlusion-notes.md).
template <bool kNative, int kSide>
[[gnu::always_inline]] inline Points tangent(const HullStack& h, const Points& q) {
    Ints down = (h.size >= 2) & seesHigher<kSide>(q, h.top, h.second);
    Ints c = h.size + down;
    Points at = select(down, h.second, h.top);
    down &= (h.size >= 3) & seesHigher<kSide>(q, at, h.third);
    c += down;
    at = select(down, h.third, at);
    down &= (h.size >= 4) & seesHigher<kSide>(q, at, h.fourth);
    c += down;
    at = select(down, h.fourth, at);
    if constexpr (kHeld == 7) {
        down &= (h.size >= 5) & seesHigher<kSide>(q, at, h.fifth);
        c += down;
        at = select(down, h.fifth, at);
        down &= (h.size >= 6) & seesHigher<kSide>(q, at, h.sixth);
        c += down;
        at = select(down, h.sixth, at);
        down &= (h.size >= 7) & seesHigher<kSide>(q, at, h.seventh);
        c += down;
        at = select(down, h.seventh, at);
    }
    while (any<kNative>(down)) {
        const Points one = gather(h.points, slot(max(c - 1, Ints{})));
        const Points two = gather(h.points, slot(max(c - 2, Ints{})));
        down &= (c > 1) & seesHigher<kSide>(q, at, one);
        c += down;
        at = select(down, one, at);
        down &= (c > 1) & seesHigher<kSide>(q, at, two);
        c += down;
        at = select(down, two, at);
    }
    return at;
}

// Pushes p (after every point of the stack in t when forward, before when not), popping what it hides.
template <bool kNative, bool kForward>
[[gnu::always_inline]] inline void push(HullStack& h, const Points& p) {
    for (;;) {
        const Floats o = kForward ? orient(h.second, h.top, p) : orient(p, h.top, h.second);
        const Ints pop = (h.size >= 2) & (o >= 0.0f);
        if (!any<kNative>(pop)) break;
        h.size += pop;
        h.top = select(pop, h.second, h.top);
        h.second = select(pop, h.third, h.second);
        h.third = select(pop, h.fourth, h.third);
        if constexpr (kHeld == 7) {
            h.fourth = select(pop, h.fifth, h.fourth);
            h.fifth = select(pop, h.sixth, h.fifth);
            h.sixth = select(pop, h.seventh, h.sixth);
            h.seventh = select(pop, gather(h.points, slot(max(h.size - 6, Ints{}))), h.seventh);
        } else {
            h.fourth = select(pop, gather(h.points, slot(max(h.size - 3, Ints{}))), h.fourth);
        }
    }
    h.size += 1;
    scatter(h.points, slot(h.size), p);
    if constexpr (kHeld == 7) {
        h.seventh = h.sixth;
        h.sixth = h.fifth;
        h.fifth = h.fourth;
    }
    h.fourth = h.third;
    h.third = h.second;
    h.second = h.top;
    h.top = p;
}

// One side's far field at every step k of the line group: the highest elevation over the samples of its
// window (first..last in DirectionPlan::Side: between kNear steps and R away), raising tan. Side 0
// pushes the line's samples onto one upper hull from its first and its texels ask in order of k; side 1
// pushes them from the last and asks from the last texel (Timonen & Westerholm's sweep, one hull per
// side). A hull holds every sample from the line's start up to the window's near end, so its tangent
// from the texel is the highest sample over the window and beyond R:
// - inside the window, it is the window's answer;
// - beyond R and no higher than tan h, nothing in the window can raise tan h either;
// - beyond R and higher (about 2 % of the texels at R = 1 tile; more where R is short, but then the
//   window is short), the lane reads the window itself, nearest first, in runs of kRun samples, and
//   skips every run whose highest sample at its nearest distance cannot beat what the lane has.
template <bool kNative, int kSide>
[[gnu::always_inline]] inline void farFieldOfSide(const float* zmap, const DirectionPlan& plan,
                                                  GroupWork& work, bool cosineWeights) {
    const float* z = work.z.data();
    // Always inlined, as everything here: at -O0 a call between code built for different ISAs would not
    // agree on where a wide vector goes (GCC's -Wpsabi).
    const auto zAt = [&](int s) __attribute__((always_inline)) {
        return load(z + static_cast<std::ptrdiff_t>(s) * kLanes);
    };
    const float* t = plan.sampleT.data();
    const auto dt = static_cast<float>(plan.dir.dt);
    const DirectionPlan::Side& w = plan.sides[kSide];
    HullStack hull{work.hull.data()};
    // How far the point at t = to lies from the texel at t = from, on this side.
    const auto away = [](auto from, auto to) __attribute__((always_inline)) {
        return kSide == 0 ? from - to : to - from;
    };
    int next = kSide == 0 ? 0 : static_cast<int>(plan.sampleT.size()) - 1;  // the next sample to push
    for (int i = 0; i < plan.sizeA; ++i) {
        const int k = kSide == 0 ? i : plan.sizeA - 1 - i;
        const auto kk = static_cast<std::size_t>(k);
        const int first = w.first[kk];
        const int last = w.last[kk];
        const float tP = static_cast<float>(k) * dt;
        const Floats zP = load(zmap + plan.texelIndex[kk]);
        float* out = work.tan[kSide].data() + static_cast<std::ptrdiff_t>(k) * kLanes;
        Floats best = load(out);
        if constexpr (kSide == 0) {
            for (; next <= last; ++next) push<kNative, true>(hull, {splat(t[next]), zAt(next)});
        } else {
            for (; next >= first; --next) push<kNative, false>(hull, {splat(t[next]), zAt(next)});
        }
        const Points h = tangent<kNative, kSide>(hull, {splat(tP), zP});
        const Floats elevation = (h.z - zP) / away(tP, h.t);
        const Ints beyond = kSide == 0 ? h.t < t[first] : h.t > t[last];
        const Ints raises = elevation > best;
        const Ints unsure = beyond & raises;
        best = (raises & ~beyond) ? elevation : best;
        if (any<kNative>(unsure)) {
            Floats found = best;
            const float* runHighest = work.runHighest.data();
            for (int r = (kSide == 0 ? last : first) / kRun;; r += kSide == 0 ? -1 : 1) {
                const int s0 = std::max(r * kRun, first);
                const int s1 = std::min(r * kRun + kRun - 1, last);
                const float nearest = away(tP, t[kSide == 0 ? s1 : s0]);
                if (any<kNative>(unsure & ((load(runHighest + static_cast<std::ptrdiff_t>(r) * kLanes) - zP) >
                                           found * nearest))) {
                    // Divides only where a sample may beat found: rise > found (1 - 2^-20) distance holds
                    // for every sample whose elevation, rounded, exceeds found (>= 0).
                    const Floats margin = found * (1.0f - 0x1p-20f);
                    Ints beats{};
                    for (int s = s0; s <= s1; ++s) beats |= (zAt(s) - zP) > margin * away(tP, t[s]);
                    if (any<kNative>(unsure & beats))
                        for (int s = s0; s <= s1; ++s) found = max(found, (zAt(s) - zP) / away(tP, t[s]));
                }
                if (r == (kSide == 0 ? first : last) / kRun) break;
            }
            best = unsure ? found : best;
        }
        store(out, result(best, cosineWeights));
    }
}

// The group's heights at sample s of the line.
[[gnu::always_inline]] inline Floats sampleAt(const float* zmap, const DirectionPlan& plan, std::size_t s) {
    const float w = plan.sampleW[s];
    return (1.0f - w) * load(zmap + plan.sampleIndex0[s]) + w * load(zmap + plan.sampleIndex1[s]);
}

// Raises each lane's tan (per side and step k: near field and the point at R) to its far field.
template <bool kNative>
[[gnu::always_inline]] inline void farFieldOfGroup(const float* zmap, const DirectionPlan& plan,
                                                   GroupWork& work, bool cosineWeights) {
    const std::size_t count = plan.sampleT.size();
    work.z.resize(count * kLanes);
    work.hull.resize(2 * (count + 2) * kLanes);
    float* z = work.z.data();
    // Per run of kRun samples, its highest: the bound that lets a lane reading its window skip a run.
    const auto run = static_cast<std::size_t>(kRun);
    work.runHighest.resize((count + run - 1) / run * kLanes);
    Floats highestInRun{};
    for (std::size_t s = 0; s < count; ++s) {
        const Floats zs = sampleAt(zmap, plan, s);
        store(z + s * kLanes, zs);
        highestInRun = s % run == 0 ? zs : max(highestInRun, zs);
        if ((s + 1) % run == 0 || s + 1 == count)
            store(work.runHighest.data() + s / run * kLanes, highestInRun);
    }
    farFieldOfSide<kNative, 0>(zmap, plan, work, cosineWeights);
    if (plan.paired) farFieldOfSide<kNative, 1>(zmap, plan, work, cosineWeights);
}

// The far field where every window is short (DirectionPlan::readWindows, at most kShortWindow
// samples): each texel reads its window's samples. The hull's numbers (its tangent is the window's highest
// sample, by the same division), but for ties between equally high samples, to float rounding.
template <bool kNative>
[[gnu::always_inline]] inline void shortFarFieldOfGroup(const float* zmap, const DirectionPlan& plan,
                                                        GroupWork& work, bool cosineWeights) {
    const std::size_t count = plan.sampleT.size();
    work.z.resize(count * kLanes);
    float* z = work.z.data();
    for (std::size_t s = 0; s < count; ++s) store(z + s * kLanes, sampleAt(zmap, plan, s));
    const float* t = plan.sampleT.data();
    const auto dt = static_cast<float>(plan.dir.dt);
    for (int side = 0; side < (plan.paired ? 2 : 1); ++side) {
        const DirectionPlan::Side& w = plan.sides[side];
        for (int k = 0; k < plan.sizeA; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const float tP = static_cast<float>(k) * dt;
            const Floats zP = load(zmap + plan.texelIndex[kk]);
            float* out = work.tan[side].data() + static_cast<std::ptrdiff_t>(k) * kLanes;
            Floats best = load(out);
            for (int i = w.first[kk]; i <= w.last[kk]; ++i)
                best = max(best, (load(z + static_cast<std::ptrdiff_t>(i) * kLanes) - zP) /
                                     (side == 0 ? tP - t[i] : t[i] - tP));
            store(out, result(best, cosineWeights));
        }
    }
}

// tan h of the texels of lines [j, j + kLanes) at every step k into work.tan[side] (lane l is line
// j + l; lines past sizeB repeat the first ones and are computed, not used). With cosineWeights, each
// result becomes the direction's term of the cosine-weighted AO instead (result()), computed here with
// the kernel's vector width.
template <bool kNative>
[[gnu::always_inline]] inline void horizonsOfGroup(const PaddedRelief& relief, const DirectionPlan& plan,
                                                   int j, GroupWork& work, bool cosineWeights) {
    const float* zmap = relief.data() + j;
    const std::ptrdiff_t entries = static_cast<std::ptrdiff_t>(plan.sizeA) * kLanes;
    for (int side = 0; side < (plan.paired ? 2 : 1); ++side) {
        work.tan[side].resize(static_cast<std::size_t>(entries));
        // The near field and the point at R; the far field then raises them and gives the results.
        nearFieldOfGroup<kNative>(zmap, plan, plan.near[static_cast<std::size_t>(side)],
                                  plan.hasFar ? &plan.sides[side] : nullptr, cosineWeights && !plan.hasFar,
                                  work.tan[side].data());
    }
    if (plan.hasFar && plan.readWindows)
        shortFarFieldOfGroup<kNative>(zmap, plan, work, cosineWeights);
    else if (plan.hasFar)
        farFieldOfGroup<kNative>(zmap, plan, work, cosineWeights);
}

// NOLINTEND(llvm-header-guard)
