// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/pipeline/Report.h"

#include <mutex>
#include <nlohmann/json.hpp>

#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"

namespace vdbmap {
namespace {

std::string joinPath(const std::vector<std::string>& path) {
    std::string out;
    for (const auto& key : path) out += (out.empty() ? "" : ".") + key;
    return out;
}

}  // namespace

struct Report::Impl {
    mutable std::mutex mutex;
    nlohmann::json root = nlohmann::json::object();

    /// The slot at `path`, creating objects on the way. Throws InvalidInput when a prefix of
    /// the path already holds a non-object value.
    nlohmann::json& slot(const std::vector<std::string>& path) {
        if (path.empty()) throw InvalidInput("Report: empty key path");
        nlohmann::json* node = &root;
        for (std::size_t i = 0; i < path.size(); ++i) {
            if (path[i].empty()) throw InvalidInput("Report: empty key in '" + joinPath(path) + "'");
            if (node->is_null()) *node = nlohmann::json::object();
            if (!node->is_object()) {
                throw InvalidInput("Report: '" + joinPath({path.begin(), path.begin() + i}) +
                                   "' is a value, cannot set '" + joinPath(path) + "'");
            }
            node = &(*node)[path[i]];
        }
        return *node;
    }

    template <typename T>
    void set(const std::vector<std::string>& path, T&& value) {
        std::lock_guard<std::mutex> lock(mutex);
        slot(path) = std::forward<T>(value);
    }
};

Report::Report() : impl_(std::make_unique<Impl>()) {}
Report::~Report() = default;

void Report::set(const std::vector<std::string>& path, double value) { impl_->set(path, value); }
void Report::set(const std::vector<std::string>& path, std::int64_t value) {
    impl_->set(path, value);
}
void Report::set(const std::vector<std::string>& path, bool value) { impl_->set(path, value); }
void Report::set(const std::vector<std::string>& path, const std::string& value) {
    impl_->set(path, value);
}

void Report::set(const std::vector<std::string>& path, const std::vector<double>& values) {
    impl_->set(path, values);
}
void Report::set(const std::vector<std::string>& path, const std::vector<std::int64_t>& values) {
    impl_->set(path, values);
}
void Report::set(const std::vector<std::string>& path, const std::vector<std::string>& values) {
    impl_->set(path, values);
}

void Report::setJson(const std::vector<std::string>& path, const std::string& json_text) {
    nlohmann::json parsed = nlohmann::json::parse(json_text, nullptr, false);
    if (parsed.is_discarded()) {
        throw InvalidInput("Report: value for '" + joinPath(path) + "' is not valid JSON: " +
                           json_text.substr(0, 80));
    }
    impl_->set(path, std::move(parsed));
}

void Report::add(const std::vector<std::string>& path, std::int64_t delta) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    nlohmann::json& node = impl_->slot(path);
    if (node.is_null()) node = std::int64_t{0};
    if (!node.is_number_integer()) {
        throw InvalidInput("Report: '" + joinPath(path) + "' is not an integer counter");
    }
    node = node.get<std::int64_t>() + delta;
}

std::string Report::toJson(int indent) const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    // Replace invalid UTF-8 (e.g. from a file name) instead of throwing.
    return impl_->root.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string Report::getJson(const std::vector<std::string>& path) const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    const nlohmann::json* node = &impl_->root;
    for (const auto& key : path) {
        if (!node->is_object() || !node->contains(key)) return "null";
        node = &(*node)[key];
    }
    return node->dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void Report::write(const std::filesystem::path& path) const {
    writeFileAtomically(path, toJson(2) + "\n");
}

}  // namespace vdbmap
