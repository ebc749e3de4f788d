//! Scene runner: a small JSON scene description → Bullet world → poses CSV. (Issue 2.)
