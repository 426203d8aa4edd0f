//! Walking a naga module's statements, nested blocks included: what the specialisation
//! (`specialise.rs`) and the baking (`bake.rs`) both read a function's body with.

use naga::{Block, Statement};

/// Calls `f` on every statement of the block, nested ones included.
pub(super) fn visit(block: &Block, f: &mut dyn FnMut(&Statement)) {
    for statement in block.iter() {
        f(statement);
        match statement {
            Statement::If { accept, reject, .. } => {
                visit(accept, f);
                visit(reject, f);
            }
            Statement::Block(b) => visit(b, f),
            Statement::Loop {
                body, continuing, ..
            } => {
                visit(body, f);
                visit(continuing, f);
            }
            Statement::Switch { cases, .. } => cases.iter().for_each(|c| visit(&c.body, f)),
            _ => {}
        }
    }
}
