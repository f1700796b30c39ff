#pragma once

// The 1-D solve of the global smoothers: (I + L) x = r on a path graph, where L is the graph Laplacian with
// edge weights e[i] >= 0 between nodes i and i + 1, i.e. the tridiagonal rows
//     -e[i-1] x[i-1] + (1 + e[i-1] + e[i]) x[i] - e[i] x[i+1] = r[i].
// Header-only and generic over the value type: float or double for one line, or a GCC vector of floats
// whose lanes are independent lines (neighbouring rows or columns of an image) solved in lockstep.

#include <array>
#include <cstddef>
#include <type_traits>

namespace dc::processing {

// The scalar type of a value type: itself for float and double, the element type for a GCC vector.
template <class V> struct LaneTraits { using Scalar = std::remove_cvref_t<decltype(std::declval<V>()[0])>; };
template <> struct LaneTraits<float> { using Scalar = float; };
template <> struct LaneTraits<double> { using Scalar = double; };

// A V read from / written to `p` without any alignment assumption (a vector of lanes may start anywhere in
// a row): through a copy of the type whose alignment is that of its scalars, which compiles to one
// unaligned load or store (memcpy of a wide vector does not, with GCC 12). Vectors pass by reference: a wide
// vector passed by value would change the calling convention with the instruction set.
template <class V> struct Unaligned {
    using Type [[gnu::aligned(alignof(typename LaneTraits<V>::Scalar)), gnu::may_alias]] = V;
};
template <class V> void loadLanes(V& v, const typename LaneTraits<V>::Scalar* p) {
    v = *reinterpret_cast<const typename Unaligned<V>::Type*>(p);
}
template <class V> void storeLanes(typename LaneTraits<V>::Scalar* p, const V& v) {
    *reinterpret_cast<typename Unaligned<V>::Type*>(p) = v;
}

// Solves (I + scale * L) x = r for K right-hand sides of one system, in place: element i of edge[] and of
// each rhs[k] lies at i * stride scalars from its base, and edge[n - 1] is not read. With G > 1, G systems
// side by side: group g's lanes start g * (lanes of V) scalars after each element's base (independent
// chains of work that hide each other's latency). `forward` holds n * G * (lanes of V) scalars of scratch.
//
// Thomas elimination without pivoting, rewritten so that every quantity is a sum or product of
// non-negative numbers: with p[i] = 1 + e[i-1] h[i-1] (the pivot minus e[i]), m[i] = p[i] + e[i] (the pivot),
// h[i] = p[i] / m[i] and g[i] = e[i] / m[i] (the eliminated upper diagonal, negated),
//     y[i] = (r[i] + e[i-1] y[i-1]) / m[i],   x[i] = y[i] + g[i] x[i+1].
// The textbook form computes the pivot as b[i] - a[i] c'[i-1], a difference of two numbers that both grow
// with e: with e ~ 1e6 it cancels to the 1 that makes the system regular and loses every digit of it. Here
// the pivot is >= 1 + e[i], the multipliers g, h lie in [0, 1], and no step subtracts, so each value is
// exact to a few rounding errors however large the weights (a near-singular system included).
template <class V, std::size_t K, int G = 1>
void solvePathLaplacian(int n, const typename LaneTraits<V>::Scalar* edge,
                        const std::array<typename LaneTraits<V>::Scalar*, K>& rhs, std::ptrdiff_t stride,
                        typename LaneTraits<V>::Scalar scale, typename LaneTraits<V>::Scalar* forward) {
    using S = typename LaneTraits<V>::Scalar;
    constexpr std::ptrdiff_t kGroupLanes = sizeof(V) / sizeof(S);
    if (n <= 0)
        return;
    V previousEdge[G] = {}, previousH[G] = {};
    V previousY[G][K] = {};
    for (int i = 0; i < n; ++i) {
#pragma GCC unroll 8
        for (int g = 0; g < G; ++g) {
            const std::ptrdiff_t at = i * stride + g * kGroupLanes;
            V e{};
            if (i + 1 < n) {
                loadLanes(e, edge + at);
                e *= scale;
            }
            const V p = S(1) + previousEdge[g] * previousH[g];
            const V inverse = S(1) / (p + e);
#pragma GCC unroll 8
            for (std::size_t k = 0; k < K; ++k) {
                V r;
                loadLanes(r, rhs[k] + at);
                previousY[g][k] = (r + previousEdge[g] * previousY[g][k]) * inverse;
                storeLanes(rhs[k] + at, previousY[g][k]);
            }
            storeLanes(forward + (i * G + g) * kGroupLanes, V(e * inverse));
            previousH[g] = p * inverse;
            previousEdge[g] = e;
        }
    }
    V next[G][K] = {};
    for (int i = n - 1; i >= 0; --i)
#pragma GCC unroll 8
        for (int g = 0; g < G; ++g) {
            const std::ptrdiff_t at = i * stride + g * kGroupLanes;
            V multiplier;
            loadLanes(multiplier, forward + (i * G + g) * kGroupLanes);
#pragma GCC unroll 8
            for (std::size_t k = 0; k < K; ++k) {
                V y;
                loadLanes(y, rhs[k] + at);
                next[g][k] = y + multiplier * next[g][k];
                storeLanes(rhs[k] + at, next[g][k]);
            }
        }
}

} // namespace dc::processing
