#include <Eigen/Dense>
#include <chrono>
#include <cstdio>
int main() {
  const int n = 30, m = 8;
  Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, n); A = A * A.transpose() + n * Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd R = Eigen::MatrixXd::Random(n, m), X(n, m);
  Eigen::LLT<Eigen::MatrixXd> llt(n);
  Eigen::Matrix<double, 30, 30> Af = A; Eigen::Matrix<double, 30, 8> Rf = R, Xf;
  Eigen::LLT<Eigen::Matrix<double, 30, 30>> lltf;
  Eigen::MatrixXd B(n, n), W = Eigen::MatrixXd::Random(n, 40);
  double sink = 0; const int N = 200000;
  auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < N; ++k) { A(0, 0) += 1e-12; llt.compute(A); X = llt.solve(R); sink += X(0, 0); }
  auto t1 = std::chrono::steady_clock::now();
  for (int k = 0; k < N; ++k) { Af(0, 0) += 1e-12; lltf.compute(Af); Xf = lltf.solve(Rf); sink += Xf(0, 0); }
  auto t2 = std::chrono::steady_clock::now();
  for (int k = 0; k < N; ++k) { W(0, 0) += 1e-12; B.noalias() = W.lazyProduct(W.transpose()); sink += B(1, 1); }
  auto t3 = std::chrono::steady_clock::now();
  auto us = [&](auto a, auto b) { return std::chrono::duration<double>(b - a).count() / N * 1e6; };
  std::printf("dynamic LLT 30 + 8 solves: %.2f us; fixed-size: %.2f us; B = W W^T (30x40): %.2f us (%g)\n",
              us(t0, t1), us(t1, t2), us(t2, t3), sink);
}
