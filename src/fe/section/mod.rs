//! Sections: fiber sections integrating uniaxial materials; elastic sections.
