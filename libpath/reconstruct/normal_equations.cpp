#include "reconstruct/normal_equations.h"

#include <cmath>

namespace lt {

namespace {

// The weight of a residual: the square of its sqrt-weight, as Ceres sees it (so both backends solve the
// same equations), or 1 without weights.
double weight(const std::vector<float>& sqrtWeights, size_t p) {
    if (sqrtWeights.empty()) return 1.0;
    const double s = sqrtWeights[p];
    return s * s;
}

// Row p = (x, y) of the normal matrix: the couplings to the four neighbours (0 where the neighbour is
// outside the image) and the diagonal. Row p of Dx^T W_x Dx holds the differences (p-1, p) and (p, p+1)
// that contain pixel p; Dy likewise.
struct Stencil {
    double up, left, center, right, down; // the off-diagonal entries are the negatives of these weights
};
Stencil stencilAt(uint32_t W, uint32_t H, uint32_t x, uint32_t y, double alpha2, const ResidualWeights& weights) {
    const size_t p = size_t(y) * W + x;
    Stencil s;
    s.left = x > 0 ? weight(weights.dx, p - 1) : 0;
    s.right = x + 1 < W ? weight(weights.dx, p) : 0;
    s.up = y > 0 ? weight(weights.dy, p - W) : 0;
    s.down = y + 1 < H ? weight(weights.dy, p) : 0;
    s.center = alpha2 * weight(weights.primal, p) + s.left + s.right + s.up + s.down;
    return s;
}

} // namespace

void assembleNormalMatrix(uint32_t width, uint32_t height, double alpha, const ResidualWeights& weights,
                          NormalMatrix& A) {
    const uint32_t W = width, H = height;
    const size_t N = size_t(W) * H;
    // Interior rows have 5 entries; the border loses one per missing neighbour.
    const size_t nonZeros = 5 * N - 2 * size_t(H) - 2 * size_t(W);
    if (size_t(A.rows()) != N || size_t(A.nonZeros()) != nonZeros) {
        A.resize(Eigen::Index(N), Eigen::Index(N));
        A.resizeNonZeros(Eigen::Index(nonZeros));
    }
    // Filled in place in compressed storage: a triplet list would cost 80 bytes per pixel more.
    int* outer = A.outerIndexPtr();
    int* inner = A.innerIndexPtr();
    double* value = A.valuePtr();
    size_t k = 0;
    const double alpha2 = alpha * alpha;
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            const size_t p = size_t(y) * W + x;
            outer[p] = int(k);
            const Stencil s = stencilAt(W, H, x, y, alpha2, weights);
            const auto put = [&](size_t column, double v) {
                inner[k] = int(column);
                value[k++] = v;
            };
            // Columns in increasing order, as compressed storage requires.
            if (y > 0) put(p - W, -s.up);
            if (x > 0) put(p - 1, -s.left);
            put(p, s.center);
            if (x + 1 < W) put(p + 1, -s.right);
            if (y + 1 < H) put(p + W, -s.down);
        }
    outer[N] = int(k);
}

void normalRightHandSide(const GradientImage& image, size_t c, double alpha, const ResidualWeights& weights,
                         Eigen::VectorXd& b) {
    const uint32_t W = image.width, H = image.height;
    const float *P = image.primal[c].data(), *gx = image.dx[c].data(), *gy = image.dy[c].data();
    b.resize(Eigen::Index(image.pixels()));
    const double alpha2 = alpha * alpha;
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            const size_t p = size_t(y) * W + x;
            // (Dx^T v)_p = v_{p-1} - v_p, the two differences that contain pixel p.
            double v = alpha2 * weight(weights.primal, p) * P[p];
            if (x > 0) v += weight(weights.dx, p - 1) * gx[p - 1];
            if (x + 1 < W) v -= weight(weights.dx, p) * gx[p];
            if (y > 0) v += weight(weights.dy, p - W) * gy[p - W];
            if (y + 1 < H) v -= weight(weights.dy, p) * gy[p];
            b[Eigen::Index(p)] = v;
        }
}

double normalResidual(uint32_t width, uint32_t height, double alpha, const ResidualWeights& weights,
                      const Eigen::VectorXd& b, const Eigen::Ref<const Eigen::VectorXd>& x) {
    const uint32_t W = width, H = height;
    const double alpha2 = alpha * alpha;
    double residual2 = 0;
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t px = 0; px < W; ++px) {
            const size_t p = size_t(y) * W + px;
            const Stencil s = stencilAt(W, H, px, y, alpha2, weights);
            double Ax = s.center * x[Eigen::Index(p)];
            if (y > 0) Ax -= s.up * x[Eigen::Index(p - W)];
            if (px > 0) Ax -= s.left * x[Eigen::Index(p - 1)];
            if (px + 1 < W) Ax -= s.right * x[Eigen::Index(p + 1)];
            if (y + 1 < H) Ax -= s.down * x[Eigen::Index(p + W)];
            const double r = b[Eigen::Index(p)] - Ax;
            residual2 += r * r;
        }
    const double b2 = b.squaredNorm();
    // b = 0: the solution is 0, and any other x is off by its whole residual.
    return b2 > 0 ? std::sqrt(residual2 / b2) : std::sqrt(residual2);
}

} // namespace lt
