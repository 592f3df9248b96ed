//! lsubdiv facade
