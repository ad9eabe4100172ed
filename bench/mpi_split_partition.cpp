// SPDX-License-Identifier: Apache-2.0
// `mpi_split_partition PARTS < costs`: the split of vdbmap-mpi (partitionContiguous, the code
// the ranks run) of the costs on standard input (one per line, in finish order) into PARTS
// contiguous runs; prints each item's part, one per line. bench/mpi_split_paper.py uses it to
// predict larger runs from measured per-tile costs (docs/benchmarks/scale.md).
#include <iostream>
#include <string>
#include <vector>

#include "vdbmap/pipeline/TilePlan.h"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: mpi_split_partition PARTS < costs\n";
        return 2;
    }
    const int parts = std::stoi(argv[1]);
    std::vector<double> costs;
    for (double c; std::cin >> c;) costs.push_back(c);
    try {
        for (const int p : vdbmap::partitionContiguous(costs, parts)) std::cout << p << '\n';
    } catch (const std::exception& e) {
        std::cerr << "mpi_split_partition: " << e.what() << '\n';
        return 2;
    }
    return 0;
}
