//! Difference bound matrices (clock zones). Implementation in progress.
