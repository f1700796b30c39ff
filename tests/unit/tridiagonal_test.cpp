// The path-graph solve of the global smoother against a dense elimination with partial pivoting in long
// double, on small random systems: ordinary ones, near-singular ones (edge weights up to 1e8, where I + L
// has condition numbers ~1e9), zero and tiny weights, several right-hand sides, strided storage and lanes.

#include "processing/tridiagonal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace dc::processing {
namespace {

using Dense = std::vector<std::vector<long double>>;

// Gaussian elimination with partial pivoting of the dense (I + scale L), for one right-hand side.
std::vector<long double> denseSolve(const std::vector<double>& edge, double scale, std::vector<double> rhs) {
    const std::size_t n = rhs.size();
    Dense a(n, std::vector<long double>(n + 1, 0.0L));
    for (std::size_t i = 0; i < n; ++i) {
        a[i][i] = 1.0L;
        a[i][n] = rhs[i];
    }
    for (std::size_t i = 0; i + 1 < n; ++i) {
        const long double e = static_cast<long double>(edge[i]) * scale;
        a[i][i] += e;
        a[i + 1][i + 1] += e;
        a[i][i + 1] -= e;
        a[i + 1][i] -= e;
    }
    for (std::size_t col = 0; col < n; ++col) {
        std::size_t pivot = col;
        for (std::size_t r = col + 1; r < n; ++r)
            if (std::fabs(a[r][col]) > std::fabs(a[pivot][col]))
                pivot = r;
        std::swap(a[col], a[pivot]);
        for (std::size_t r = col + 1; r < n; ++r) {
            const long double f = a[r][col] / a[col][col];
            for (std::size_t c = col; c <= n; ++c)
                a[r][c] -= f * a[col][c];
        }
    }
    std::vector<long double> x(n);
    for (std::size_t i = n; i-- > 0;) {
        long double s = a[i][n];
        for (std::size_t c = i + 1; c < n; ++c)
            s -= a[i][c] * x[c];
        x[i] = s / a[i][i];
    }
    return x;
}

struct System {
    std::vector<double> edge, rhs;
};

System randomSystem(std::mt19937_64& rng, int n, double maxLogEdge) {
    std::uniform_real_distribution<double> logEdge(-6.0, maxLogEdge), value(-1.0, 1.0);
    std::bernoulli_distribution cut(0.1);
    System s{std::vector<double>(static_cast<std::size_t>(n)),
             std::vector<double>(static_cast<std::size_t>(n))};
    for (int i = 0; i < n; ++i) {
        s.edge[static_cast<std::size_t>(i)] = cut(rng) ? 0.0 : std::pow(10.0, logEdge(rng));
        s.rhs[static_cast<std::size_t>(i)] = value(rng);
    }
    return s;
}

// max |x - reference| / max |reference| over the system.
template <class T> double relativeError(const std::vector<T>& x, const std::vector<long double>& reference) {
    long double worst = 0.0L, scale = 0.0L;
    for (std::size_t i = 0; i < x.size(); ++i) {
        worst = std::max(worst, std::fabs(static_cast<long double>(x[i]) - reference[i]));
        scale = std::max(scale, std::fabs(reference[i]));
    }
    return static_cast<double>(worst / scale);
}

template <class T> std::vector<T> solveOne(const System& s, double scale) {
    std::vector<T> edge(s.edge.begin(), s.edge.end()), x(s.rhs.begin(), s.rhs.end());
    std::vector<T> forward(x.size());
    solvePathLaplacian<T, 1>(static_cast<int>(x.size()), edge.data(), {x.data()}, 1, static_cast<T>(scale),
                             forward.data());
    return x;
}

TEST(Tridiagonal, MatchesADenseSolveOnRandomSystems) {
    std::mt19937_64 rng(11);
    for (int trial = 0; trial < 200; ++trial) {
        const int n = 1 + trial % 40;
        const System s = randomSystem(rng, n, 2.0);
        const std::vector<long double> reference = denseSolve(s.edge, 1.0, s.rhs);
        EXPECT_LE(relativeError(solveOne<double>(s, 1.0), reference), 1e-13) << "trial " << trial;
        EXPECT_LE(relativeError(solveOne<float>(s, 1.0), reference), 2e-6) << "trial " << trial;
    }
}

// With weights up to 1e8, I + L is within 1e-8 of the singular L: textbook elimination computes its pivots
// as differences of numbers ~1e8 and loses the 1 that makes them nonzero. Ours must keep full precision.
TEST(Tridiagonal, NearSingularSystemsKeepTheirPrecision) {
    std::mt19937_64 rng(12);
    for (int trial = 0; trial < 200; ++trial) {
        const int n = 2 + trial % 30;
        const System s = randomSystem(rng, n, 8.0);
        const std::vector<long double> reference = denseSolve(s.edge, 1.0, s.rhs);
        EXPECT_LE(relativeError(solveOne<double>(s, 1.0), reference), 1e-11) << "trial " << trial;
        EXPECT_LE(relativeError(solveOne<float>(s, 1.0), reference), 1e-5) << "trial " << trial;
    }
}

TEST(Tridiagonal, ZeroWeightsDecoupleAndAreTheIdentity) {
    const System s{{0.0, 0.0, 0.0, 0.0}, {0.5, -2.0, 3.0, 7.0}};
    const std::vector<double> x = solveOne<double>(s, 1.0);
    for (std::size_t i = 0; i < x.size(); ++i)
        EXPECT_EQ(x[i], s.rhs[i]);
}

TEST(Tridiagonal, AConstantIsPreservedExactly) {
    // (I + L) c = c for a constant c: every row sums to 1. Smoothing a constant must not move it.
    std::mt19937_64 rng(13);
    System s = randomSystem(rng, 50, 6.0);
    std::fill(s.rhs.begin(), s.rhs.end(), 1.25);
    for (double x : solveOne<double>(s, 1.0))
        EXPECT_NEAR(x, 1.25, 1e-12);
}

TEST(Tridiagonal, ScaleMultipliesEveryWeight) {
    std::mt19937_64 rng(14);
    System s = randomSystem(rng, 25, 1.0);
    System scaled = s;
    for (double& e : scaled.edge)
        e *= 37.0;
    EXPECT_LE(relativeError(solveOne<double>(s, 37.0), denseSolve(scaled.edge, 1.0, scaled.rhs)), 1e-13);
}

TEST(Tridiagonal, SeveralRightHandSidesAndAStride) {
    std::mt19937_64 rng(15);
    const int n = 17, stride = 3;
    const System s = randomSystem(rng, n, 3.0);
    const System t = randomSystem(rng, n, 3.0);
    std::vector<double> edge(static_cast<std::size_t>(n * stride)), a(edge.size()), b(edge.size());
    for (int i = 0; i < n; ++i) {
        edge[static_cast<std::size_t>(i * stride)] = s.edge[static_cast<std::size_t>(i)];
        a[static_cast<std::size_t>(i * stride)] = s.rhs[static_cast<std::size_t>(i)];
        b[static_cast<std::size_t>(i * stride)] = t.rhs[static_cast<std::size_t>(i)];
    }
    std::vector<double> forward(static_cast<std::size_t>(n));
    solvePathLaplacian<double, 2>(n, edge.data(), {a.data(), b.data()}, stride, 1.0, forward.data());
    const std::vector<long double> ra = denseSolve(s.edge, 1.0, s.rhs), rb = denseSolve(s.edge, 1.0, t.rhs);
    for (int i = 0; i < n; ++i) {
        EXPECT_NEAR(a[static_cast<std::size_t>(i * stride)],
                    static_cast<double>(ra[static_cast<std::size_t>(i)]), 1e-13);
        EXPECT_NEAR(b[static_cast<std::size_t>(i * stride)],
                    static_cast<double>(rb[static_cast<std::size_t>(i)]), 1e-13);
        EXPECT_EQ(a[static_cast<std::size_t>(i * stride + 1)], 0.0)
            << "between the strides nothing is touched";
    }
}

// Lanes of a vector are independent systems, each solved exactly as the scalar code solves it.
TEST(Tridiagonal, LanesSolveIndependentSystems) {
    using Lanes4 = float __attribute__((vector_size(4 * sizeof(float))));
    std::mt19937_64 rng(16);
    const int n = 33;
    std::vector<System> systems;
    for (int lane = 0; lane < 4; ++lane)
        systems.push_back(randomSystem(rng, n, 4.0));
    std::vector<float> edge(static_cast<std::size_t>(4 * n)), x(edge.size());
    for (int i = 0; i < n; ++i)
        for (int lane = 0; lane < 4; ++lane) {
            edge[static_cast<std::size_t>(4 * i + lane)] = static_cast<float>(systems[lane].edge[i]);
            x[static_cast<std::size_t>(4 * i + lane)] = static_cast<float>(systems[lane].rhs[i]);
        }
    std::vector<float> forward(static_cast<std::size_t>(4 * n));
    solvePathLaplacian<Lanes4, 1>(n, edge.data(), {x.data()}, 4, 1.0f, forward.data());
    for (int lane = 0; lane < 4; ++lane) {
        const std::vector<float> scalar = solveOne<float>(systems[lane], 1.0);
        for (int i = 0; i < n; ++i)
            EXPECT_EQ(x[static_cast<std::size_t>(4 * i + lane)], scalar[static_cast<std::size_t>(i)])
                << "lane " << lane << " node " << i;
    }
}

} // namespace
} // namespace dc::processing
