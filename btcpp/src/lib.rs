//! BehaviorTree.CPP interoperability: its v4 XML in and out, behavior sets from its
//! `<TreeNodesModel>`, and Groot2's replay logs.
//!
//! ```
//! use std::path::Path;
//! use btcpp::xml::{import_text, ImportOptions};
//!
//! let xml = r#"
//! <root BTCPP_format="4">
//!   <BehaviorTree ID="Main">
//!     <ReactiveSequence>
//!       <BatteryOk/>
//!       <MoveTo goal="{target}" speed="0.5"/>
//!     </ReactiveSequence>
//!   </BehaviorTree>
//!   <TreeNodesModel>
//!     <Condition ID="BatteryOk"/>
//!     <Action ID="MoveTo">
//!       <input_port name="goal" type="Pose"/>
//!       <input_port name="speed" type="double"/>
//!     </Action>
//!   </TreeNodesModel>
//! </root>"#;
//! let imported = import_text(Path::new("main.xml"), xml, &ImportOptions::default())?;
//! assert_eq!(imported.nodes.len(), 3);
//! assert_eq!(imported.slots[0].name, "target");
//! # Ok::<(), btcpp::ImportError>(())
//! ```
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod btlog;
mod error;
pub mod groot2;
pub mod kinds;
pub mod xml;

pub use error::{Fault, ImportError, Location};
