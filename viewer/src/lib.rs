//! The interactive viewer's logic that does not need a window, shared by the binary and its
//! tests: the fly camera ([`fly`]), the scripted input of test runs ([`script`]), the scene
//! set-up ([`scene`]), so that a test can render headlessly exactly what the window showed, the
//! instances a user adds and removes by handle ([`instances`]), and the shader hot reload
//! ([`hot_reload`]).

pub mod fly;
pub mod hot_reload;
pub mod instances;
pub mod scene;
pub mod script;
