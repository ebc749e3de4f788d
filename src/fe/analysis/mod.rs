//! Analyses: gravity (load control), modal (eigen), transient (Newmark + Newton).
