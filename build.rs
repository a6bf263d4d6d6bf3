//! Generates the GL bindings for the fixed-function entry points the GL_SELECT backend
//! needs (glSelectBuffer, glRenderMode, glPushName/glLoadName, glMatrixMode, glLoadMatrixd,
//! glClipPlane, glBegin/glVertex3d/glEnd, their queries ...): GL 2.1 compatibility profile
//! plus glBindProgramPipeline,
//! as a struct loaded at run time through the caller's get_proc_address. Everything newer
//! goes through glow.

use gl_generator::{Api, Fallbacks, Profile, Registry, StructGenerator};
use std::env;
use std::fs::File;
use std::path::Path;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let dest = env::var("OUT_DIR").unwrap();
    let mut file = File::create(Path::new(&dest).join("gl_compat.rs")).unwrap();
    // glBindProgramPipeline (separate shader objects): GL_SELECT draws with no program, so
    // a host's bound pipeline is set aside while it selects.
    Registry::new(
        Api::Gl,
        (2, 1),
        Profile::Compatibility,
        Fallbacks::None,
        ["GL_ARB_separate_shader_objects"],
    )
    .write_bindings(StructGenerator, &mut file)
    .unwrap();
}
