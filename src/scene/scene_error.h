#pragma once
// The one error type of scene input (files, manifests, scene names). Its message is one line that
// names the file and, where known, the line; the CLI prints it as is.
#include <stdexcept>
#include <string>

namespace trident {

class SceneError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A triangle that references a vertex the mesh does not have: its own type so that callers which
/// map errors to kinds (the Python module's IndexError) need not read the message.
class SceneIndexError : public SceneError {
public:
    using SceneError::SceneError;
};

}  // namespace trident
