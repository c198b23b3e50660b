// lieservo/configurable.hpp — the one configuration lifecycle of the stateful classes (the
// filter and the controllers): Options, static validate(options) → Status, configure(options)
// → Status, configurationStatus(), step(…) → Status.
//
// Written once here: configure() runs the class's validate() first, so a refused configure()
// changes nothing; a constructor given options keeps the refusal as configurationStatus(), and
// the class's step() returns it until a configure() succeeds.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <lieservo/status.hpp>

namespace lieservo {

/// CRTP base of a configurable class `Derived`, which provides
///   static Status validate(const Options&) noexcept   the whole check, parts' options included;
///   Status apply(const Options&) noexcept             takes options that validate() passed
///                                                     (configures the parts, stores them);
/// and befriends this base when apply() is private.
template <class Derived>
class Configurable {
 public:
  /// ok, or why the constructor's options were refused: step() returns it until a configure()
  /// succeeds (a configure() that fails changes nothing, this included).
  Status configurationStatus() const noexcept { return status_; }

 protected:
  Configurable() = default;

  /// validate(), then apply(): the body of Derived::configure().
  template <class Options>
  Status configureChecked(const Options& options) noexcept {
    if (const Status s = Derived::validate(options); s != Status::ok) return s;
    if (const Status s = static_cast<Derived&>(*this).apply(options); s != Status::ok) return s;
    status_ = Status::ok;
    return Status::ok;
  }

  /// For a constructor given options: configures and keeps the result.
  template <class Options>
  void configureOnConstruction(const Options& options) noexcept {
    status_ = configureChecked(options);
  }

 private:
  Status status_ = Status::ok;
};

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>
