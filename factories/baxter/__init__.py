"""baxter"""
