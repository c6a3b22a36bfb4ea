//! FRF-based model updating (Yan & Golinval): SEREP reduction, FRF and
//! natural-frequency sensitivity equations, SVD solution, composed parameters.
