//! The `shadowtruth/scene/v1` file format, read field by field so that every problem is reported.
