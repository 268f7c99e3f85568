//! What the tables compare: one of the project's methods, or a front made by another tool.

use super::method::Method;
use serde::Serialize;
use std::fmt;

/// A column of the tables: a method run here, or an outside front by its given name.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(untagged)]
pub enum Contender {
    /// A method of the project.
    Method(Method),
    /// An outside tool's front, re-scored here; one sample, so no spread and no rank-sum test.
    External(String),
}

impl Contender {
    /// The name the tables and the figure show: the method's label, or the given name.
    pub(crate) fn label(&self) -> &str {
        match self {
            Contender::Method(m) => m.label(),
            Contender::External(name) => name,
        }
    }

    /// A short key for the figure's `data-method` attribute: the method's command-line name,
    /// or the given name.
    pub(crate) fn key(&self) -> &str {
        match self {
            Contender::Method(m) => m.name(),
            Contender::External(name) => name,
        }
    }

    /// The method, when it is one.
    pub(crate) fn method(&self) -> Option<Method> {
        match self {
            Contender::Method(m) => Some(*m),
            Contender::External(_) => None,
        }
    }
}

/// So that code looking for a method's column can compare directly.
impl PartialEq<Method> for Contender {
    fn eq(&self, other: &Method) -> bool {
        self.method() == Some(*other)
    }
}

impl From<Method> for Contender {
    fn from(m: Method) -> Self {
        Contender::Method(m)
    }
}

impl fmt::Display for Contender {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.label())
    }
}
