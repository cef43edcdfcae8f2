//! The one kind of problem the glTF reader reports.

/// A problem in a glTF file: its JSON path (`nodes[3].rotation`) and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct GltfProblem {
    pub path: String,
    pub message: String,
}

impl GltfProblem {
    pub(crate) fn new(path: impl Into<String>, message: impl Into<String>) -> Self {
        GltfProblem { path: path.into(), message: message.into() }
    }
}
