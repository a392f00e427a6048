// What the experiments share: the command line (--quick), the independent exhaustive oracle
// of the character merit, continued fractions, seeded random numbers, and the side-by-side
// table each program prints (the paper's figure beside ours).
#pragma once

#include "compiler/lower/Characters.h"

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace moire::exp {

using G = lower::Grad<double>;

// --quick: the small variant ctest runs, with its own assertion. Anything else is an error
// (exit status 2, with a usage line).
struct Options {
    bool quick = false;
};
Options parseOptions(int argc, char** argv, const char* what);

// The exhaustive minimum of mu_k over every character with 1 <= |k_i| <= maxOrder, by a plain
// loop over integer pairs. Independent of compiler/lower/Characters.h on purpose (its own
// copy of Eq. 11-12), so that it can judge the shipped search: it is the oracle.
struct Exhaustive {
    double mu = 0.0;
    int k1 = 0, k2 = 0; // k1 > 0
};
double oracleMerit(int k1, int k2, G g1, G g2);
Exhaustive exhaustiveMinimum(G g1, G g2, int maxOrder);

// The same, as the order budget grows: entry n - 1 is the winner over max |k_i| <= n.
std::vector<Exhaustive> exhaustiveLadder(G g1, G g2, int maxOrder);

// The convergents p_n / q_n of x's continued fraction (x > 0), as far as q_n <= maxQ or the
// expansion ends (an exact rational, to double precision).
struct Fraction {
    int64_t p, q;
};
std::vector<Fraction> convergents(double x, int64_t maxQ);

// The shipped per-pixel search, in double (Characters.h's bestPairCharacter).
struct Shipped {
    double mu;
    int k1, k2, k3; // k3: the third layer's, for a stack of three
};
Shipped shippedPair(G g1, G g2);
// The same search as the kernel's IR (stackCharacter over layers with these gradients,
// bottom to top), run on the reference interpreter.
Shipped stackKernel(const std::vector<G>& g);

// "(k1, k2)" or "(k1, k2, k3)", signed so that the first nonzero coefficient is positive.
std::string characterName(int k1, int k2, int k3 = 0, bool three = false);

// True when characters a and b are the same (k and -k are one character).
bool sameCharacter(int a1, int a2, int b1, int b2);

// A gradient of magnitude 1 / pitch in direction `angle` (radians).
G gradientOf(double pitch, double angle);

// Table output: a title, then rows of (quantity, the paper's figure, ours).
void printTitle(const std::string& title);
void printRow(const std::string& what, const std::string& paper, const std::string& ours);
std::string percent(double fraction);

// The final line: "PASS" or "FAIL: why", and the exit status to return (0 or 1).
int verdict(bool ok, const std::string& why);

} // namespace moire::exp
