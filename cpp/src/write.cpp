// A brush writing on a paper: the deposit, then the ink's state update.
#include "brushwork/write.hpp"

namespace brushwork {

namespace {

template <typename P>
DepositStats deposit_on(P& paper, Brush& brush, Ink* ink) {
  const DepositStats stats = paper.deposit(brush.frame(), ink);
  if (ink != nullptr) brush.spend_ink(stats, paper.scene(), *ink);
  return stats;
}

}  // namespace

DepositStats deposit(Paper& paper, Brush& brush, Ink* ink) { return deposit_on(paper, brush, ink); }

DepositStats deposit(VectorPaper& paper, Brush& brush, Ink* ink) { return deposit_on(paper, brush, ink); }

}  // namespace brushwork
