// Provenance (validation/provenance.h): SHA-256 against the FIPS 180-4 / NIST CAVP example
// digests, block-boundary lengths against an independent chaining identity, and the version.
#include "vcmm/validation/provenance.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace {

using vcmm::validation::file_sha256;
using vcmm::validation::sha256_hex;

TEST(Sha256, NistExampleDigests) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmno"
                       "ijklmnopjklmnopqklmnopqrlmnopqrsmnopqrstnopqrstu"),
            "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1");
  EXPECT_EQ(sha256_hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, EveryLengthAroundTheBlockBoundaryGivesADistinctWellFormedDigest) {
  // Lengths 0…130 cross both padding cases (one or two final blocks); all digests differ.
  std::set<std::string> seen;
  for (std::size_t n = 0; n <= 130; ++n) {
    const std::string d = sha256_hex(std::string(n, 'x'));
    ASSERT_EQ(d.size(), 64u);
    EXPECT_EQ(d.find_first_not_of("0123456789abcdef"), std::string::npos);
    EXPECT_TRUE(seen.insert(d).second) << n;
  }
  // 55 and 56 bytes: the last length fitting one padded block and the first needing two.
  EXPECT_EQ(sha256_hex(std::string(55, 'a')),
            "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318");
  EXPECT_EQ(sha256_hex(std::string(56, 'a')),
            "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a");
}

TEST(Provenance, VersionAndRevisionAreRecorded) {
  EXPECT_EQ(std::string(vcmm::validation::vcmm_version()), "0.1.0");
  EXPECT_FALSE(vcmm::validation::vcmm_revision().empty());
  EXPECT_THROW(file_sha256("/nonexistent/model.json"), std::invalid_argument);
}

}  // namespace
