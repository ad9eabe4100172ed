// SPDX-License-Identifier: Apache-2.0
// Test plugin: the first stage is fine, the second throws when constructed.
#include <stdexcept>

#include "vdbmap/plugin/Plugin.h"

namespace {

class FineStage : public vdbmap::Stage {
public:
    std::string_view name() const override { return "badreg.fine"; }
    void declareOptions(vdbmap::OptionSpec&) override {}
    void run(vdbmap::Context&) override {}
};

class ThrowingStage : public vdbmap::Stage {
public:
    ThrowingStage() { throw std::runtime_error("constructor failed on purpose"); }
    std::string_view name() const override { return "badreg.throwing"; }
    void declareOptions(vdbmap::OptionSpec&) override {}
    void run(vdbmap::Context&) override {}
};

}  // namespace

VDBMAP_PLUGIN("badreg", FineStage, ThrowingStage)
