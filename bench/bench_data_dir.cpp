#include "bench_data_dir.hpp"

namespace facet::bench {

const char* const k_bench_data_dir = FACET_BENCH_DATA_DIR;

}  // namespace facet::bench
