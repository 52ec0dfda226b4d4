#include "sim/tally/table.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "models/core/statistics.h"

namespace mcref {

namespace {

std::string full_digits(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

}  // namespace

Axis Axis::bins(std::string name, std::string unit, std::vector<double> edges) {
  if (edges.size() < 2) throw std::invalid_argument("axis " + name + " needs at least 2 edges");
  for (std::size_t i = 0; i < edges.size(); ++i)
    if (!std::isfinite(edges[i]) || (i > 0 && !(edges[i] > edges[i - 1])))
      throw std::invalid_argument("axis " + name + ": bin edges must be finite and increasing (edge " + std::to_string(i) +
                                  " is " + full_digits(edges[i]) + (i > 0 ? ", after " + full_digits(edges[i - 1]) : "") + ")");
  return {std::move(name), std::move(unit), Kind::Bins, std::move(edges)};
}

Axis Axis::uniform_bins(std::string name, std::string unit, double lo, double hi, int n) {
  std::vector<double> e(n + 1);
  for (int i = 0; i <= n; ++i) e[i] = lo + (hi - lo) * i / n;
  e[n] = hi;
  return bins(std::move(name), std::move(unit), std::move(e));
}

Axis Axis::points(std::string name, std::string unit, std::vector<double> values) {
  if (values.empty()) throw std::invalid_argument("axis " + name + " needs at least 1 point");
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      throw std::invalid_argument("axis " + name + ": point " + std::to_string(i) + " is not finite");
  return {std::move(name), std::move(unit), Kind::Points, std::move(values)};
}

int Axis::find_bin(double x) const {
  if (!(x >= values.front() && x < values.back())) return -1;
  // Uniform bins are the common case; fall back to bisection.
  const std::size_t n = values.size() - 1;
  std::size_t i = static_cast<std::size_t>((x - values.front()) / (values.back() - values.front()) * n);
  if (i >= n) i = n - 1;
  if (x >= values[i] && x < values[i + 1]) return static_cast<int>(i);
  std::size_t lo = 0, hi = n;
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    (x < values[mid] ? hi : lo) = mid;
  }
  return static_cast<int>(lo);
}

Table::Table(std::string name_, std::string quantity_, std::vector<Axis> axes_)
    : name(std::move(name_)), quantity(std::move(quantity_)), axes(std::move(axes_)) {
  std::size_t n = 1;
  for (const Axis& a : axes) n *= a.size();
  sum.assign(n, 0.0);
  sum_sq.assign(n, 0.0);
}

std::vector<std::size_t> Table::shape() const {
  std::vector<std::size_t> s;
  for (const Axis& a : axes) s.push_back(a.size());
  return s;
}

std::size_t Table::index(const std::vector<std::size_t>& idx) const {
  std::size_t k = 0;
  for (std::size_t d = 0; d < axes.size(); ++d) k = k * axes[d].size() + idx[d];
  return k;
}

void Table::add_batch(const std::vector<double>& estimate) {
  if (estimate.size() != sum.size()) throw std::logic_error("batch size mismatch in table " + name);
  for (std::size_t i = 0; i < sum.size(); ++i) {
    sum[i] += estimate[i];
    sum_sq[i] += estimate[i] * estimate[i];
  }
  if (keep_batch_values) batch_values.insert(batch_values.end(), estimate.begin(), estimate.end());
  ++batches;
}

void Table::merge(const Table& other) {
  if (other.name != name || other.axes.size() != axes.size() || other.sum.size() != sum.size())
    throw std::invalid_argument("cannot merge table " + other.name + " into " + name);
  for (std::size_t d = 0; d < axes.size(); ++d)
    if (!(axes[d] == other.axes[d])) throw std::invalid_argument("axes differ in table " + name);
  for (std::size_t i = 0; i < sum.size(); ++i) {
    sum[i] += other.sum[i];
    sum_sq[i] += other.sum_sq[i];
  }
  if (keep_batch_values) {
    if (other.has_batch_values())
      batch_values.insert(batch_values.end(), other.batch_values.begin(), other.batch_values.end());
    else if (other.batches == 1)  // its sums are its one batch's estimates (0 + x = x)
      batch_values.insert(batch_values.end(), other.sum.begin(), other.sum.end());
    else if (other.batches > 0) {
      keep_batch_values = false;
      batch_values.clear();
      batch_values.shrink_to_fit();
    }
  }
  batches += other.batches;
  for (const auto& [key, text] : other.attributes) {
    auto it = attributes.find(key);
    if (it == attributes.end()) {
      attributes[key] = text;
      continue;
    }
    for (const char* count : kCountAttributes)
      if (key == count) it->second = std::to_string(std::stoll(it->second) + std::stoll(text));
  }
}

double Table::value(std::size_t i) const { return batches > 0 ? sum[i] / batches : NAN; }

double Table::stderr_of(std::size_t i) const {
  if (batches < 2) return NAN;
  return stderr_of_mean(sum[i], sum_sq[i], static_cast<double>(batches));
}

std::vector<double> Table::values() const {
  std::vector<double> v(cells());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = value(i);
  return v;
}

std::vector<double> Table::stderrs() const {
  std::vector<double> v(cells());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = stderr_of(i);
  return v;
}

}  // namespace mcref
